// The distributed static contact solve (fem/distributed_contact.h) against the condensed sole
// at the same mesh (coupling::CondensedSole + contact/'s semismooth Newton, dense): agreement of
// the nodal forces and of the node states, and the cost of each (issue 26). Prints a table;
// never passes or fails (bench/README.md). The case of scenes/static_contact.prm: the sole box
// (HRP-2 foot, 2 cm, E = 4 MPa, nu = 0.3) in 11 x 7 x 1 Q1 hexahedra refined r times, the foot
// pressed 0.15 mm, tilted 0.002 rad, pushed 0.05 mm, mu = 0.5. One rank.
//   static_contact_condensed_bench [max_refinements (default 2)]
#include "contact/contact_solver.h"
#include "coupling/condensed_sole.h"
#include "fem/distributed_contact.h"
#include "tests/fem/sole_box_grid.h"

#include <deal.II/base/mpi.h>
#include <deal.II/grid/grid_generator.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <map>
#include <tuple>

using namespace plantar;
using dealii::Point;
using dealii::Tensor;

namespace {

constexpr double length = 0.2172, width = 0.138, thickness = 0.02;

void make_sole(dealii::Triangulation<3>& tria, unsigned int refinements) {
  fem::test::make_sole_box(tria, 11, 7, 1, refinements);
}

double since(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

} // namespace

int main(int argc, char** argv) {
  dealii::Utilities::MPI::MPI_InitFinalize mpi(argc, argv, 1);
  const unsigned int max_refinements = argc > 1 ? std::atoi(argv[1]) : 2;
  const fem::MaterialTable materials{fem::LinearElasticMaterial(4e6, 0.3)};
  fem::RigidMotion foot;
  foot.translation = Tensor<1, 3>({0.05e-3, 0, -0.15e-3});
  foot.rotation = Tensor<1, 3>({0, 0.002, 0});
  foot.center = Point<3>(0, 0, thickness);
  const double friction = 0.5;
  std::printf("| refinements | DoF | contact nodes | full: s | condensation: s | condensed "
              "contact solve: s | max abs(f - f_full) / max abs(f) | states differing |\n"
              "| --- | --- | --- | --- | --- | --- | --- | --- |\n");
  for (unsigned int r = 0; r <= max_refinements; ++r) {
    dealii::Triangulation<3> coarse;
    make_sole(coarse, 0);
    fem::DistributedContactSettings settings;
    settings.refinements = r;
    settings.friction = friction;
    settings.tolerance = 1e-12;
    auto start = std::chrono::steady_clock::now();
    fem::DistributedContact full(MPI_COMM_SELF, coarse, materials, settings);
    full.solve(foot);
    const double full_time = since(start);
    const auto nodes = full.gather_contact_nodes();

    dealii::Triangulation<3> tria;
    make_sole(tria, r);
    start = std::chrono::steady_clock::now();
    coupling::CondensationParameters parameters;
    const coupling::CondensedSole sole(tria, materials, parameters);
    const double condensation_time = since(start);
    const int n = sole.n_contacts();
    contact::ContactProblem problem;
    problem.resize(n, 0);
    problem.n_contacts = n;
    contact::CompliantPatch patch;
    patch.first_contact = 0;
    patch.n_contacts = n;
    patch.compliance_over_dt = sole.compliance();
    patch.rotation << 0, 0, 1, 1, 0, 0, 0, 1, 0;
    problem.patches.push_back(patch);
    for (int k = 0; k < n; ++k) {
      const Point<3> x(sole.contact_positions()(k, 0), sole.contact_positions()(k, 1),
                       sole.contact_positions()(k, 2));
      const Tensor<1, 3> u = foot.displacement(x);
      problem.free_velocity.segment<3>(3 * k) << u[2], u[0], u[1];
      problem.normal_bias[k] = x[2];
      problem.friction[k] = friction;
    }
    contact::SolverSettings solver_settings;
    solver_settings.solver = contact::ContactSolverType::newton;
    solver_settings.newton_linear_solve = contact::NewtonLinearSolve::dense;
    solver_settings.tolerance = 1e-14;
    solver_settings.max_iterations = 500;
    solver_settings.warm_start = false;
    solver_settings.sticking_direct = false;
    start = std::chrono::steady_clock::now();
    contact::ContactSolver solver(n, 0, contact::ContactSolverType::newton);
    Eigen::VectorXd impulses = Eigen::VectorXd::Zero(3 * n);
    const auto result = solver.solve(problem, solver_settings, impulses);
    const double contact_time = since(start);

    std::map<std::tuple<long long, long long>, Tensor<1, 3>> reference;
    double max_force = 0;
    for (int k = 0; k < n; ++k) {
      Tensor<1, 3> f;
      f[0] = impulses[3 * k + 1];
      f[1] = impulses[3 * k + 2];
      f[2] = impulses[3 * k];
      reference[{std::llround(sole.contact_positions()(k, 0) * 1e9),
                 std::llround(sole.contact_positions()(k, 1) * 1e9)}] = f;
      max_force = std::max(max_force, f.norm());
    }
    double difference = 0;
    unsigned int differing = 0;
    for (const auto& node : nodes) {
      const Tensor<1, 3>& f = reference.at(
          {std::llround(node.position[0] * 1e9), std::llround(node.position[1] * 1e9)});
      difference = std::max(difference, (node.force - f).norm());
      const fem::NodeState state = f[2] <= 1e-9 * max_force ? fem::NodeState::separated
                                   : std::hypot(f[0], f[1]) >= friction * f[2] * (1 - 1e-7)
                                       ? fem::NodeState::slip
                                       : fem::NodeState::stick;
      differing += state != node.state;
    }
    std::printf("| %u | %u | %d | %.3g | %.3g | %.3g (%s) | %.2e | %u |\n", r,
                static_cast<unsigned int>(full.n_dofs()), n, full_time, condensation_time,
                contact_time,
                result.status == contact::SolverStatus::converged ? "converged" : "NOT converged",
                difference / max_force, differing);
    std::fflush(stdout);
  }
  return 0;
}
