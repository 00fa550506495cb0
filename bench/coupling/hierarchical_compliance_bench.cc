// The FEM sole's compliance compressed as an H-matrix (contact/hierarchical_compliance.h)
// against the dense one, for decreasing mesh size h: storage, compression time and error, and
// one contact solve of a rigid foot landing on the sole (Gauss-Seidel on the dense and on the
// compressed patch: time, sweeps, difference of the impulses). The HRP-2 sole of
// meshes/sole_box.geo (0.2172 x 0.138 x 0.02 m, Q1, E = 4 MPa, nu = 0.3), top face bonded.
// A timing app, not a test: prints a table, never passes or fails.
// Usage: hierarchical_compliance_bench [h1 h2 ...] (m).
#include "bench/coupling/sole_box_condensation.h"
#include "contact/contact_solver.h"
#include "contact/hierarchical_compliance.h"

#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <vector>

using namespace plantar;

namespace {

double seconds_since(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

// A 60 kg rigid foot (inertia 0.2, 0.5, 0.6 kg m^2 about its centre 5 cm above the sole's
// contact face) landing at 0.3 m/s, rolling at 1 rad/s and sliding at 0.05 m/s: one step of
// dt = 1 ms, the patch block C/dt^2, mu = 0.6.
struct FootStep {
  contact::ContactProblem problem;
  contact::ContactSolver solver;
  FootStep(const Eigen::MatrixX3d& nodes, const Eigen::MatrixXd* dense,
           const contact::HierarchicalCompliance* compressed) {
    const int n = static_cast<int>(nodes.rows());
    const double dt = 1e-3, mass = 60.0;
    const Eigen::Vector3d inertia(0.2, 0.5, 0.6);
    const Eigen::Vector3d centre = nodes.colwise().mean().transpose() + Eigen::Vector3d(0, 0, 0.05);
    problem.resize(n, 6);
    problem.n_contacts = n;
    Eigen::MatrixXd jacobian(3 * n, 6);
    Eigen::Matrix3d frame; // rows: n, t1, t2
    frame << 0, 0, 1, 1, 0, 0, 0, 1, 0;
    for (int c = 0; c < n; ++c) {
      const Eigen::Vector3d r = nodes.row(c).transpose() - centre;
      Eigen::Matrix3d skew;
      skew << 0, -r.z(), r.y(), r.z(), 0, -r.x(), -r.y(), r.x(), 0;
      jacobian.block<3, 3>(3 * c, 0) = frame;
      jacobian.block<3, 3>(3 * c, 3) = -frame * skew;
    }
    Eigen::VectorXd inv_sqrt(6);
    inv_sqrt << Eigen::Vector3d::Constant(1.0 / std::sqrt(mass)),
        inertia.cwiseSqrt().cwiseInverse();
    problem.rigid_factor = jacobian * inv_sqrt.asDiagonal();
    Eigen::VectorXd u_free(6);
    u_free << 0.05, 0.0, -0.3, 1.0, 0.0, 0.0;
    problem.free_velocity = jacobian * u_free;
    problem.normal_bias.setZero();
    problem.friction.setConstant(0.6);
    contact::CompliantPatch patch;
    patch.n_contacts = n;
    if (compressed != nullptr) {
      patch.compressed = compressed;
      patch.compressed_scale = 1.0 / (dt * dt);
    } else {
      patch.compliance_over_dt = *dense / (dt * dt);
    }
    problem.patches.push_back(std::move(patch));
    solver.resize(n, 6, contact::ContactSolverType::gauss_seidel);
  }
};

struct SolveRun {
  double seconds = 0;
  int sweeps = 0;
  bool converged = false;
  Eigen::VectorXd impulses;
};

SolveRun solve(FootStep& step) {
  contact::SolverSettings settings;
  settings.solver = contact::ContactSolverType::gauss_seidel;
  settings.tolerance = 1e-10;
  settings.max_iterations = 5000;
  settings.warm_start = false;
  SolveRun run;
  run.impulses.setZero(3 * step.problem.n_contacts);
  const auto start = std::chrono::steady_clock::now();
  const contact::SolverResult result = step.solver.solve(step.problem, settings, run.impulses);
  run.seconds = seconds_since(start);
  run.sweeps = result.iterations;
  run.converged = result.status == contact::SolverStatus::converged;
  return run;
}

} // namespace

int main(int argc, char** argv) {
  std::vector<double> sizes = {0.02, 0.01, 0.0075, 0.005};
  if (argc > 1) {
    sizes.clear();
    for (int i = 1; i < argc; ++i)
      sizes.push_back(std::atof(argv[i]));
  }
  std::printf("H-matrix compliance of the HRP-2 sole (Q1, E = 4 MPa, nu = 0.3), leaf 16 nodes, "
              "eta 2; one Gauss-Seidel contact solve (tolerance 1e-10 m/s) of a landing foot\n");
  std::printf("%7s %6s %8s %6s | %9s %8s %8s %9s %5s | %9s %6s %9s %6s %10s\n", "h (m)", "n_c",
              "cond s", "dense MB", "tolerance", "H MB", "H % ", "rel err", "rank", "dense s",
              "sweeps", "H s", "sweeps", "|dp|/|p|");
  for (const double h : sizes) {
    const auto t0 = std::chrono::steady_clock::now();
    const auto sole = bench::condense_sole_box(h);
    const double condensation = seconds_since(t0);
    const Eigen::MatrixXd& c = sole.compliance();
    const Eigen::MatrixX3d& nodes = sole.contact_positions();
    FootStep dense_step(nodes, &c, nullptr);
    const SolveRun dense = solve(dense_step);
    for (const double tolerance : {1e-4, 1e-6, 1e-8}) {
      contact::HierarchicalSettings settings;
      settings.tolerance = tolerance;
      const auto t1 = std::chrono::steady_clock::now();
      const auto hc = contact::HierarchicalCompliance::from_dense(nodes, c, settings);
      const double compression = seconds_since(t1);
      const double error = (hc.to_dense() - c).norm() / c.norm();
      FootStep step(nodes, nullptr, &hc);
      const SolveRun run = solve(step);
      const double difference = (run.impulses - dense.impulses).norm() / dense.impulses.norm();
      std::printf("%7.4f %6d %8.2f %6.1f | %9.0e %8.2f %7.1f%% %9.2e %5d | %9.4f %6d%s %9.4f "
                  "%6d%s %10.2e   (compression %.2f s)\n",
                  h, sole.n_contacts(), condensation, hc.dense_bytes() / 1048576.0, tolerance,
                  hc.bytes() / 1048576.0, 100.0 * hc.bytes() / hc.dense_bytes(), error,
                  hc.max_rank(), dense.seconds, dense.sweeps, dense.converged ? " " : "!",
                  run.seconds, run.sweeps, run.converged ? " " : "!", difference, compression);
      std::fflush(stdout);
    }
  }
  return 0;
}
