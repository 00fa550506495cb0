// The distributed static contact solve (fem/distributed_contact.h, issue 26), run under mpirun
// at 1 and 2 ranks:
// (a) frictionless flat punch: a sole pressed down by delta with mu = 0 keeps every bottom node
//     on the ground and gives the reaction of the linear solve with u_z = 0 prescribed on the
//     bottom (serial deal.II, UMFPACK);
// (b) the condensed reference: the same mesh condensed serially (coupling::CondensedSole) and its
//     static contact problem (W = C, dt = 1) solved by contact/'s semismooth Newton give the same
//     nodal forces and the same separated/stick/slip sets, for a tilted foot pressed and pushed
//     sideways (mu = 0.5: part of the sole lifts off, part slips); at 2 ranks the solve equals
//     the one on each rank alone (MPI_COMM_SELF) to 1e-10;
// (c) force balance: the bottom nodes' forces and the foot's force sum to zero;
// (d) GMRES on the Newton increment with BoomerAMG or GAMG (rigid-body modes) reaches the
//     tolerance with the forces and node states of the MUMPS solve;
// force control (fem/foot_load_control.h): the force and moments of a displacement-controlled
// solve, given as the load, give back its displacement.
#include "contact/contact_solver.h"
#include "coupling/condensed_sole.h"
#include "fem/discretization.h"
#include "fem/distributed_contact.h"
#include "fem/foot_load_control.h"
#include "fem/linear_elasticity.h"
#include "tests/fem/sole_box_grid.h"

#include <deal.II/base/mpi.h>
#include <deal.II/grid/grid_generator.h>
#include <deal.II/lac/sparse_direct.h>
#include <deal.II/numerics/matrix_tools.h>

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <map>
#include <tuple>

namespace plantar::fem {
namespace {

using dealii::Point;
using dealii::Tensor;

constexpr double length = 0.2172, width = 0.138, thickness = 0.02, E = 4e6, nu = 0.3;

bool rank0() {
  return dealii::Utilities::MPI::this_mpi_process(MPI_COMM_WORLD) == 0;
}

void make_sole(dealii::Triangulation<3>& tria, unsigned int n_x, unsigned int n_y, unsigned int n_z,
               unsigned int refinements = 0) {
  fem::test::make_sole_box(tria, n_x, n_y, n_z, refinements);
}

std::tuple<long long, long long> xy_key(const Point<3>& p) {
  return {std::llround(p[0] * 1e9), std::llround(p[1] * 1e9)};
}

TEST(DistributedContact, FrictionlessFlatPunchEqualsLinearSolve) {
  const double delta = 1e-3;
  for (const unsigned int degree : {1u, 2u}) {
    dealii::Triangulation<3> coarse;
    make_sole(coarse, 8, 6, 2);
    const MaterialTable materials{LinearElasticMaterial(E, nu)};
    DistributedContactSettings settings;
    settings.degree = degree;
    settings.refinements = 1;
    settings.friction = 0;
    settings.tolerance = 1e-12;
    DistributedContact problem(MPI_COMM_WORLD, coarse, materials, settings);
    RigidMotion foot;
    foot.translation[2] = -delta;
    const auto& report = problem.solve(foot);
    const Tensor<1, 3> ground = problem.ground_force();

    // The linear solve: top u = (0, 0, -delta), bottom u_z = 0, x and y free.
    dealii::Triangulation<3> tria;
    make_sole(tria, 8, 6, 2, 1);
    const Discretization discretization(CellKind::hexahedron, degree);
    LinearElasticity linear(tria, discretization, materials);
    const dealii::Functions::ConstantFunction<3> top(std::vector<double>{0, 0, -delta});
    linear.setup({{0, &top}});
    linear.assemble();
    dealii::SparseMatrix<double> matrix(linear.stiffness_matrix().get_sparsity_pattern());
    matrix.copy_from(linear.stiffness_matrix());
    dealii::Vector<double> load = linear.load(), u(load.size());
    std::map<dealii::types::global_dof_index, double> bottom;
    for (const auto& node : linear.boundary_nodes(1))
      bottom[node[2]] = 0;
    dealii::MatrixTools::apply_boundary_values(bottom, matrix, u, load);
    dealii::SparseDirectUMFPACK umfpack;
    umfpack.initialize(matrix);
    umfpack.vmult(u, load);
    linear.constraints().distribute(u);
    linear.solution() = u;
    const double reference = linear.reaction_force(1)[2];

    if (rank0())
      std::printf("Q%u, %u dofs: %u iterations, residual %.2e; normal force %.12e N, linear "
                  "solve %.12e N (rel. difference %.2e); %u of %u nodes in contact\n",
                  degree, static_cast<unsigned int>(problem.n_dofs()), report.iterations,
                  report.residual, ground[2], reference, ground[2] / reference - 1,
                  report.n_stick + report.n_slip, problem.n_contact_nodes());
    EXPECT_EQ(report.n_separated, 0u);
    EXPECT_EQ(report.n_stick, 0u); // mu = 0: every node in contact slides
    EXPECT_EQ(report.n_slip, problem.n_contact_nodes());
    EXPECT_GT(reference, 1000.0);
    EXPECT_NEAR(ground[2] / reference, 1.0, 1e-10);
    EXPECT_LT(std::abs(ground[0]) + std::abs(ground[1]), 1e-8 * reference);
    // (c) force balance.
    const Tensor<1, 3> foot_force = problem.foot_force();
    EXPECT_LT((foot_force + ground).norm(), 1e-10 * reference);
  }
}

/// The condensed reference: nodal forces (sole frame x, y, z), by xy position.
std::map<std::tuple<long long, long long>, Tensor<1, 3>>
condensed_reference(const dealii::Triangulation<3>& tria, const MaterialTable& materials,
                    const RigidMotion& foot, double friction, double tolerance, double& residual) {
  coupling::CondensationParameters parameters;
  parameters.attached_boundary = 0;
  parameters.contact_boundary = 1;
  parameters.degree = 1;
  const coupling::CondensedSole sole(tria, materials, parameters);
  const int n = sole.n_contacts();
  contact::ContactProblem problem;
  problem.resize(n, 0);
  problem.n_contacts = n;
  contact::CompliantPatch patch;
  patch.first_contact = 0;
  patch.n_contacts = n;
  patch.compliance_over_dt = sole.compliance(); // dt = 1: W = C (m/N), impulses = forces (N)
  patch.rotation << 0, 0, 1, 1, 0, 0, 0, 1, 0;  // (n, t1, t2) <- (z, x, y)
  problem.patches.push_back(patch);
  for (int k = 0; k < n; ++k) {
    const Point<3> x(sole.contact_positions()(k, 0), sole.contact_positions()(k, 1),
                     sole.contact_positions()(k, 2));
    const Tensor<1, 3> u = foot.displacement(x); // the sole moves rigidly with no contact force
    problem.free_velocity.segment<3>(3 * k) << u[2], u[0], u[1];
    problem.normal_bias[k] = x[2]; // the unloaded gap (ground z = 0)
    problem.friction[k] = friction;
  }
  contact::SolverSettings settings;
  settings.solver = contact::ContactSolverType::newton;
  settings.newton_linear_solve = contact::NewtonLinearSolve::dense;
  settings.tolerance = tolerance;
  settings.max_iterations = 500;
  settings.warm_start = false;
  settings.sticking_direct = false;
  contact::ContactSolver solver(n, 0, contact::ContactSolverType::newton);
  Eigen::VectorXd impulses = Eigen::VectorXd::Zero(3 * n);
  const auto result = solver.solve(problem, settings, impulses);
  EXPECT_EQ(result.status, contact::SolverStatus::converged) << "residual " << result.residual;
  residual = result.residual;
  std::map<std::tuple<long long, long long>, Tensor<1, 3>> forces;
  for (int k = 0; k < n; ++k) {
    const Point<3> x(sole.contact_positions()(k, 0), sole.contact_positions()(k, 1), 0);
    Tensor<1, 3> f;
    f[0] = impulses[3 * k + 1];
    f[1] = impulses[3 * k + 2];
    f[2] = impulses[3 * k];
    forces[xy_key(x)] = f;
  }
  return forces;
}

NodeState classify(const Tensor<1, 3>& f, double friction, double max_force) {
  if (f[2] <= 1e-9 * max_force)
    return NodeState::separated;
  return std::hypot(f[0], f[1]) >= friction * f[2] * (1 - 1e-7) ? NodeState::slip
                                                                : NodeState::stick;
}

TEST(DistributedContact, TiltedFootEqualsCondensedReference) {
  const double friction = 0.5;
  RigidMotion foot;
  foot.translation = Tensor<1, 3>({0.3e-3, 0.1e-3, -1.0e-3});
  foot.rotation = Tensor<1, 3>({0.004, 0.015, 0}); // toe and one side down, heel up
  foot.center = Point<3>(0, 0, thickness);
  const MaterialTable materials{LinearElasticMaterial(E, nu)};
  dealii::Triangulation<3> coarse;
  make_sole(coarse, 8, 6, 1);
  DistributedContactSettings settings;
  settings.refinements = 1;
  settings.friction = friction;
  settings.tolerance = 1e-12;
  DistributedContact problem(MPI_COMM_WORLD, coarse, materials, settings);
  const auto report = problem.solve(foot);
  const auto nodes = problem.gather_contact_nodes();

  dealii::Triangulation<3> tria;
  make_sole(tria, 8, 6, 1, 1);
  double reference_residual = 0;
  const auto reference =
      condensed_reference(tria, materials, foot, friction, 1e-14, reference_residual);
  ASSERT_EQ(reference.size(), nodes.size());
  double max_force = 0, max_difference = 0;
  for (const auto& [key, f] : reference)
    max_force = std::max(max_force, f.norm());
  unsigned int mismatched_states = 0, counts[3] = {0, 0, 0};
  for (const auto& node : nodes) {
    const auto found = reference.find(xy_key(node.position));
    ASSERT_NE(found, reference.end());
    max_difference = std::max(max_difference, (node.force - found->second).norm());
    ++counts[static_cast<int>(node.state)];
    if (classify(found->second, friction, max_force) != node.state)
      ++mismatched_states;
  }
  const Tensor<1, 3> ground = problem.ground_force(), foot_force = problem.foot_force();
  if (rank0())
    std::printf("%u dofs, %u contact nodes: %u Newton iterations, residual %.2e; separated %u, "
                "stick %u, slip %u; ground force (%.6f, %.6f, %.6f) N; condensed reference "
                "(contact/ Newton, residual %.1e m): max |f - f_ref| / max |f_ref| = %.2e, "
                "%u states differ\n",
                static_cast<unsigned int>(problem.n_dofs()), problem.n_contact_nodes(),
                report.iterations, report.residual, report.n_separated, report.n_stick,
                report.n_slip, ground[0], ground[1], ground[2], reference_residual,
                max_difference / max_force, mismatched_states);
  // The case asked for: part of the sole lifts off, part sticks, part slips.
  EXPECT_GT(counts[0], 10u);
  EXPECT_GT(counts[1], 10u);
  EXPECT_GT(counts[2], 5u);
  EXPECT_EQ(counts[0], report.n_separated);
  EXPECT_LT(max_difference / max_force, 1e-8);
  EXPECT_EQ(mismatched_states, 0u);
  // (c) force balance: the ground's and the foot's forces on the sole cancel.
  EXPECT_LT((foot_force + ground).norm(), 1e-10 * ground.norm());

  // Each rank alone (MPI_COMM_SELF) gives the distributed solution.
  if (dealii::Utilities::MPI::n_mpi_processes(MPI_COMM_WORLD) > 1) {
    DistributedContact alone(MPI_COMM_SELF, coarse, materials, settings);
    alone.solve(foot);
    const auto serial = alone.gather_contact_nodes();
    ASSERT_EQ(serial.size(), nodes.size());
    double difference = 0;
    unsigned int differing_states = 0;
    for (std::size_t k = 0; k < nodes.size(); ++k) {
      ASSERT_LT((serial[k].position - nodes[k].position).norm(), 1e-12);
      difference = std::max(difference, (serial[k].force - nodes[k].force).norm());
      differing_states += serial[k].state != nodes[k].state;
    }
    if (rank0())
      std::printf("%u ranks against 1: max |f - f_1| / max |f| = %.2e, %u states differ\n",
                  dealii::Utilities::MPI::n_mpi_processes(MPI_COMM_WORLD), difference / max_force,
                  differing_states);
    EXPECT_LT(difference / max_force, 1e-10);
    EXPECT_EQ(differing_states, 0u);
  }
}

// The iterative solvers (GMRES on the Newton increment, BoomerAMG or GAMG with the rigid-body
// modes) reach the tolerance of the MUMPS solve and its forces and node states.
TEST(DistributedContact, IterativeSolversEqualMumps) {
  RigidMotion foot;
  foot.translation = Tensor<1, 3>({0.3e-3, 0.1e-3, -1.0e-3});
  foot.rotation = Tensor<1, 3>({0.004, 0.015, 0});
  foot.center = Point<3>(0, 0, thickness);
  const MaterialTable materials{LinearElasticMaterial(E, nu)};
  dealii::Triangulation<3> coarse;
  make_sole(coarse, 8, 6, 1);
  DistributedContactSettings settings;
  settings.refinements = 1;
  settings.friction = 0.5;
  settings.tolerance = 1e-10;
  DistributedContact direct(MPI_COMM_WORLD, coarse, materials, settings);
  const auto direct_report = direct.solve(foot);
  const auto reference = direct.gather_contact_nodes();
  double max_force = 0;
  for (const auto& node : reference)
    max_force = std::max(max_force, node.force.norm());
  for (const auto solver : {ContactLinearSolver::gmres_amg, ContactLinearSolver::gmres_gamg}) {
    settings.linear_solver = solver;
    DistributedContact iterative(MPI_COMM_WORLD, coarse, materials, settings);
    const auto report = iterative.solve(foot);
    const auto nodes = iterative.gather_contact_nodes();
    ASSERT_EQ(nodes.size(), reference.size());
    double difference = 0;
    unsigned int differing_states = 0;
    for (std::size_t k = 0; k < nodes.size(); ++k) {
      difference = std::max(difference, (nodes[k].force - reference[k].force).norm());
      differing_states += nodes[k].state != reference[k].state;
    }
    if (rank0())
      std::printf("%s: %u Newton iterations (MUMPS %u), %u GMRES iterations, residual %.2e; max "
                  "|f - f_mumps| / max |f| = %.2e, %u states differ\n",
                  solver == ContactLinearSolver::gmres_amg ? "GMRES + BoomerAMG" : "GMRES + GAMG",
                  report.iterations, direct_report.iterations, report.linear_iterations,
                  report.residual, difference / max_force, differing_states);
    EXPECT_LE(report.residual, settings.tolerance);
    EXPECT_GT(report.linear_iterations, report.iterations); // GMRES ran
    EXPECT_LT(difference / max_force, 1e-8);
    EXPECT_EQ(differing_states, 0u);
  }
}

TEST(DistributedContact, ForceControlRecoversTheDisplacement) {
  RigidMotion foot;
  foot.translation = Tensor<1, 3>({0.3e-3, 0.1e-3, -1.0e-3});
  foot.rotation = Tensor<1, 3>({0.004, 0.015, 0});
  foot.center = Point<3>(0, 0, thickness);
  const MaterialTable materials{LinearElasticMaterial(E, nu)};
  dealii::Triangulation<3> coarse;
  make_sole(coarse, 8, 6, 1);
  DistributedContactSettings settings;
  settings.friction = 0.5;
  settings.tolerance = 1e-12;
  DistributedContact problem(MPI_COMM_WORLD, coarse, materials, settings);
  problem.solve(foot);
  const Tensor<1, 3> force = problem.foot_force(), moment = problem.foot_moment(foot.center);
  FootLoad load;
  load.normal_force = -force[2];
  load.moment_x = moment[0];
  load.moment_y = moment[1];
  RigidMotion start = foot;
  start.translation[2] = -0.2e-3;
  start.rotation[0] = start.rotation[1] = 0;
  FootLoadSettings load_settings;
  load_settings.tolerance = 1e-9;
  const FootLoadReport report = solve_for_foot_load(problem, load, load_settings, start);
  const Tensor<1, 3> found_force = problem.foot_force();
  const Tensor<1, 3> found_moment = problem.foot_moment(foot.center);
  if (rank0())
    std::printf("load N = %.6f N, M = (%.6f, %.6f) N m: %u quasi-Newton iterations, %u contact "
                "solves; t_z %.12e (prescribed %.12e) m, theta (%.12e, %.12e) (prescribed "
                "(%.12e, %.12e)) rad; force error %.1e, moment error %.1e\n",
                load.normal_force, load.moment_x, load.moment_y, report.iterations,
                report.contact_solves, start.translation[2], foot.translation[2], start.rotation[0],
                start.rotation[1], foot.rotation[0], foot.rotation[1], report.force_error,
                report.moment_error);
  EXPECT_GT(load.normal_force, 100.0);
  EXPECT_NEAR(found_force[2], force[2], 1e-9 * load.normal_force);
  EXPECT_NEAR(found_moment[0], moment[0], 1e-9 * load.normal_force * 0.12);
  EXPECT_NEAR(found_moment[1], moment[1], 1e-9 * load.normal_force * 0.12);
  EXPECT_NEAR(start.translation[2], foot.translation[2], 1e-6 * std::abs(foot.translation[2]));
  EXPECT_NEAR(start.rotation[0], foot.rotation[0], 1e-6 * foot.rotation[1]);
  EXPECT_NEAR(start.rotation[1], foot.rotation[1], 1e-6 * foot.rotation[1]);
}

TEST(DistributedContact, RefusesTetrahedraAndBadSettings) {
  dealii::Triangulation<3> tetrahedra;
  dealii::GridGenerator::subdivided_hyper_rectangle_with_simplices(
      tetrahedra, {2, 2, 1}, Point<3>(0, 0, 0), Point<3>(1, 1, 0.1));
  const MaterialTable materials{LinearElasticMaterial(E, nu)};
  try {
    DistributedContact problem(MPI_COMM_WORLD, tetrahedra, materials, {});
    ADD_FAILURE() << "tetrahedra accepted";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("hexahedra"), std::string::npos) << e.what();
  }
  dealii::Triangulation<3> coarse;
  make_sole(coarse, 2, 2, 1);
  DistributedContactSettings settings;
  settings.friction = -1;
  try {
    DistributedContact problem(MPI_COMM_WORLD, coarse, materials, settings);
    ADD_FAILURE() << "mu = -1 accepted";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("friction coefficient = -1"), std::string::npos)
        << e.what();
  }
  // Two Newton iterations are not enough for the tilted foot (it takes 6): a numerical
  // failure, reported.
  dealii::Triangulation<3> sole;
  make_sole(sole, 8, 6, 1);
  settings.friction = 0.5;
  settings.refinements = 1;
  settings.max_iterations = 2;
  DistributedContact problem(MPI_COMM_WORLD, sole, materials, settings);
  RigidMotion foot;
  foot.translation = Tensor<1, 3>({0.3e-3, 0.1e-3, -1e-3});
  foot.rotation = Tensor<1, 3>({0.004, 0.015, 0});
  foot.center = Point<3>(0, 0, thickness);
  try {
    problem.solve(foot);
    ADD_FAILURE() << "no failure after 1 iteration";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("did not converge after 2 iterations"), std::string::npos)
        << e.what();
  }
}

} // namespace
} // namespace plantar::fem

int main(int argc, char** argv) {
  dealii::Utilities::MPI::MPI_InitFinalize mpi(argc, argv, 1);
  ::testing::InitGoogleTest(&argc, argv);
  if (dealii::Utilities::MPI::this_mpi_process(MPI_COMM_WORLD) != 0) {
    auto& listeners = ::testing::UnitTest::GetInstance()->listeners();
    delete listeners.Release(listeners.default_result_printer());
  }
  return RUN_ALL_TESTS();
}
