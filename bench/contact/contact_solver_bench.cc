// Contact solver comparison (not a test: prints figures, never fails on time).
//
// Problem: a 60 kg rigid block (one foot carrying the robot, 6-DoF rigid part
// G = J L^-T) on a 0.2 m x 0.1 m sole of n = 50, 200, 800 contact nodes whose
// compliance is the Boussinesq-Cerruti half-space kernel (E = 4 MPa,
// nu = 0.49, paper's sole material), mu = 0.8, horizontal push 0.1 W,
// dt = 1 ms. The block is simulated for 20 steps (ADMM, 1e-10 m/s), then the
// problem of step 21 is solved repeatedly:
//   cold: from zero impulses;  warm: from the solution of step 20.
// Printed: residual (m/s, natural map) against iterations, and time per
// solve to 1e-8 m/s (max 5000 iterations), for Gauss-Seidel and ADMM:
// "first" on a freshly sized solver, "repeat" the mean of later solves of the
// same problem (ADMM then reuses its patch factorisation, as in a time loop
// at constant dt); "chol." counts patch Cholesky factorisations in all runs.
// Usage: contact_solver_bench [max_nodes]   (default 800)
#include "contact/contact_solver.h"
#include "tests/contact/boussinesq_compliance.h"
#include "tests/contact/rigid_body_harness.h"

#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <vector>

namespace pc = plantar::contact;

namespace {

struct Case {
  pc::ContactProblem problem;
  Eigen::VectorXd warm;     // solution of the previous step
  Eigen::VectorXd solution; // reference solution of this step
};

Case make_case(int n_x, int n_y) {
  const double spacing = 0.2 / n_x, mass = 60.0, dt = 1e-3;
  pc::test::RigidWorld world;
  const Eigen::Vector3d size(0.2, 0.1, 0.05);
  pc::test::RigidBody block;
  block.mass = mass;
  block.principal_inertia = pc::test::box_inertia(mass, size);
  block.position = Eigen::Vector3d(0, 0, 0.5 * size.z());
  block.force = Eigen::Vector3d(0.1 * mass * 9.81, 0, 0);
  world.bodies.push_back(block);
  const Eigen::MatrixXd nodes = pc::test::rectangular_grid(n_x, n_y, spacing);
  for (int i = 0; i < nodes.rows(); ++i) {
    pc::test::PointContact contact;
    contact.point = Eigen::Vector3d(nodes(i, 0), nodes(i, 1), -0.5 * size.z());
    contact.friction = 0.8;
    world.contacts.push_back(contact);
  }
  world.set_patch(pc::test::boussinesq_compliance(nodes, spacing, 4e6, 0.49));
  world.settings.solver = pc::ContactSolverType::admm;
  world.settings.tolerance = 1e-10;
  world.settings.max_iterations = 5000;
  world.finalize();
  const int n = static_cast<int>(nodes.rows());
  Case out;
  out.warm.resize(3 * n);
  for (int step = 0; step < 21; ++step) {
    if (step == 20)
      for (int c = 0; c < n; ++c)
        out.warm.segment<3>(3 * c) = world.impulse(c);
    world.step(dt);
  }
  out.problem = world.problem();
  out.solution.resize(3 * n);
  for (int c = 0; c < n; ++c)
    out.solution.segment<3>(3 * c) = world.impulse(c);
  return out;
}

} // namespace

int main(int argc, char** argv) {
  const int max_nodes = argc > 1 ? std::atoi(argv[1]) : 800;
  const int checkpoints[] = {1, 2, 5, 10, 20, 50, 100, 200, 500, 1000, 2000, 5000};
  std::printf("Contact solver benchmark: Boussinesq sole patch + 6-DoF rigid block (see header)\n");
  std::printf("%6s %-12s %-5s %10s %12s %12s %12s %8s %s\n", "nodes", "solver", "start",
              "iterations", "residual", "first ms", "repeat ms", "chol.", "status");
  std::vector<std::string> history_rows;
  for (const auto& [n_x, n_y] : std::vector<std::pair<int, int>>{{10, 5}, {20, 10}, {40, 20}}) {
    const int n = n_x * n_y;
    if (n > max_nodes)
      continue;
    const Case c = make_case(n_x, n_y);
    pc::ContactSolver solver(n, c.problem.rigid_rank());
    solver.record_history(5000);
    for (const auto type : {pc::ContactSolverType::gauss_seidel, pc::ContactSolverType::admm})
      for (const bool warm : {false, true}) {
        pc::SolverSettings settings;
        settings.solver = type;
        settings.tolerance = 1e-8;
        settings.max_iterations = 5000;
        Eigen::VectorXd p(3 * n);
        pc::SolverResult result;
        // First solve on a freshly sized solver (ADMM factorises), then
        // repeats (ADMM reuses the patch factor through warm rho, as in a
        // time loop with constant dt and contact set).
        solver.resize(n, c.problem.rigid_rank());
        int repeats = 0;
        double first = 0.0, seconds = 0.0;
        while (repeats < 2 || (seconds < 0.5 && repeats < 50)) {
          p = warm ? c.warm : Eigen::VectorXd::Zero(3 * n);
          settings.warm_start = warm;
          const auto t0 = std::chrono::steady_clock::now();
          result = solver.solve(c.problem, settings, p);
          const double t =
              std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
          if (repeats == 0)
            first = t;
          else
            seconds += t;
          ++repeats;
        }
        const double diff = (p - c.solution).norm() / c.solution.norm();
        std::printf("%6d %-12s %-5s %10d %12.3e %12.3f %12.3f %8ld %s (|p - p_ref|/|p_ref| = "
                    "%.1e)\n",
                    n, pc::to_string(type), warm ? "warm" : "cold", result.iterations,
                    result.residual, 1e3 * first, 1e3 * seconds / (repeats - 1),
                    solver.n_patch_factorizations(), pc::to_string(result.status), diff);
        // Residual against iterations (tolerance 0: run all 5000 recorded iterations
        // only up to the first checkpoint past convergence to 1e-12).
        settings.tolerance = 1e-12;
        p = warm ? c.warm : Eigen::VectorXd::Zero(3 * n);
        solver.solve(c.problem, settings, p);
        const Eigen::VectorXd h = solver.history();
        char row[512];
        int len = std::snprintf(row, sizeof(row), "%6d %-12s %-5s", n, pc::to_string(type),
                                warm ? "warm" : "cold");
        for (const int k : checkpoints)
          len += k <= h.size() ? std::snprintf(row + len, sizeof(row) - len, " %8.1e", h[k - 1])
                               : std::snprintf(row + len, sizeof(row) - len, " %8s", "-");
        history_rows.emplace_back(row);
      }
  }
  std::printf(
      "\nResidual (m/s) after k iterations (GS: sweeps; '-': converged to 1e-12 before k)\n");
  std::printf("%6s %-12s %-5s", "nodes", "solver", "start");
  for (const int k : checkpoints)
    std::printf(" %8d", k);
  std::printf("\n");
  for (const std::string& row : history_rows)
    std::printf("%s\n", row.c_str());
  return 0;
}
