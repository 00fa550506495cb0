// A contact problem no solver here finishes in 1,000 iterations: three collinear contacts of a
// rigid heel (step 1222 of a shortened HRP-2 walk, written by the stepper in Siconos's format:
// tests/contact/data/rigid_walk_collinear_heel.dat). W (9 x 9) has rank 5 and the normal biases
// are not compatible with the collinear contacts, so the solution has a contact near the cone's
// apex; Siconos's NSGS stalls at an error of 1.1e-7 and its NSN_AC ends at 2e-3 after 500
// iterations. Plantar's auto runs Newton from Gauss-Seidel's iterate (stopped when it stalls),
// then from the step's warm start, which converges (118 iterations in all). Without a warm start
// the restart from zero diverges here (residual 0.022 m/s), the first attempt only creeps down
// (1.2e-7 to 6e-8 m/s in 500 iterations), and Newton from zero with rho 10 x larger, auto's next
// attempt, converges in 64 iterations (664 in all): auto must converge both ways, finished by
// Newton. Checked with Siconos's own error measure and our dense residual.
#include "contact/contact_solver.h"
#include "tests/contact/siconos_format.h"
#include "tests/contact/siconos_oracle.h"

#include <algorithm>
#include <cstdio>
#include <gtest/gtest.h>

namespace plantar::contact::testing {
namespace {

/// A problem of tests/contact/data posed for Plantar's solvers, with Siconos's view of it.
struct WalkProblem {
  explicit WalkProblem(const std::string& name)
      : path(std::string(PLANTAR_SOURCE_DIR) + "/tests/contact/data/" + name),
        source(read_siconos_problem(path)), oracle(path) {
    pose_problem(source, problem);
  }
  /// The step's warm start, as the stepper passed it (name.warm.txt, written by
  /// contact/siconos_writer.h write_warm_start).
  Eigen::VectorXd warm_start() const {
    return read_warm_start(path.substr(0, path.rfind(".dat")) + ".warm.txt", problem.n_contacts);
  }
  std::string path;
  SiconosProblem source;
  SiconosOracle oracle;
  ContactProblem problem;
};

TEST(AutoRestart, ReturnsTheBetterOfNewtonsTwoAttempts) {
  const WalkProblem walk("rigid_walk_collinear_heel.dat");
  const SiconosProblem& source = walk.source;
  const SiconosOracle& oracle = walk.oracle;
  const ContactProblem& problem = walk.problem;
  ASSERT_EQ(problem.n_contacts, 3);
  ContactSolver solver(problem.n_contacts, 0);
  SolverSettings settings;
  settings.tolerance = 1e-8; // m/s, as the walk scenes
  settings.max_iterations = 1000;
  settings.warm_start = true;
  // The walk's warm start (the previous step's impulses), as the stepper passed it.
  const Eigen::VectorXd warm = walk.warm_start();

  // Newton alone from zero with the restart's budget: the attempt auto must not return.
  settings.solver = ContactSolverType::newton;
  settings.warm_start = false;
  Eigen::VectorXd from_zero = Eigen::VectorXd::Zero(9);
  const SolverResult newton = solver.solve(problem, settings, from_zero);
  settings.warm_start = true;

  settings.solver = ContactSolverType::automatic;
  Eigen::VectorXd r = warm;
  const SolverResult result = solver.solve(problem, settings, r);
  const Eigen::VectorXd u = source.dense_w() * r + source.q;
  const double dense = fc3d_error(source.dense_w(), source.q, source.mu, r);
  std::printf("Newton from zero: %d it, residual %.3e m/s; auto: %d it (%s@%d), residual %.3e "
              "m/s, Siconos error %.3e, ours %.3e, min u_n %.3e m/s\n",
              newton.iterations, newton.residual, result.iterations,
              to_string(result.switch_reason), result.switch_iteration, result.residual,
              oracle.error(r), dense, u(Eigen::seqN(0, 3, 3)).minCoeff());
  EXPECT_EQ(result.finished_by, ContactSolverType::newton);
  EXPECT_GT(newton.residual, 1e-4); // the restart's path fails on this problem
  EXPECT_TRUE(result.converged());
  EXPECT_LT(result.residual, settings.tolerance);
  // The returned impulses are the ones the residual was measured on (not the restart's).
  EXPECT_NEAR(oracle.error(r), dense, 1e-12);
  EXPECT_LT(dense, 1e-6);
  EXPECT_LT(result.residual, 1e-3 * newton.residual);

  // Without a warm start (no attempt from it): the restart from zero diverges and the retry with
  // rho x 10 converges.
  settings.warm_start = false;
  Eigen::VectorXd r_cold = Eigen::VectorXd::Zero(9);
  const SolverResult cold = solver.solve(problem, settings, r_cold);
  std::printf("auto from zero: %d it (%s@%d), residual %.3e m/s, Siconos error %.3e\n",
              cold.iterations, to_string(cold.switch_reason), cold.switch_iteration, cold.residual,
              oracle.error(r_cold));
  EXPECT_TRUE(cold.converged());
  EXPECT_EQ(cold.finished_by, ContactSolverType::newton);
  EXPECT_LT(oracle.error(r_cold), 1e-6);
}

// Four contacts of a compliant ankle's foot at a step's edge (step 3314 of the robustness
// matrix's planned step, dt 1 ms, theta 1, written by the run that stopped on it:
// tests/contact/data/compliant_ankle_step_edge.dat). Gauss-Seidel converges slowly (rate 0.89
// per sweep), so auto switches to Newton, whose matrix is singular here: Newton from its
// iterate and from zero end at 1e-4 m/s, as Siconos's NSN_AC (LU failed). Auto must then resume
// Gauss-Seidel from its own iterate, which converges; Siconos's NSGS converges too.
TEST(AutoRestart, ResumesGaussSeidelWhenNewtonFails) {
  const WalkProblem walk("compliant_ankle_step_edge.dat");
  const SiconosProblem& source = walk.source;
  const SiconosOracle& oracle = walk.oracle;
  const ContactProblem& problem = walk.problem;
  ASSERT_EQ(problem.n_contacts, 4);
  ContactSolver solver(problem.n_contacts, 0);
  SolverSettings settings;
  settings.tolerance = 1e-8; // m/s, as the walk scenes
  settings.max_iterations = 4000;
  settings.warm_start = false;
  settings.solver = ContactSolverType::newton;
  Eigen::VectorXd newton_r = Eigen::VectorXd::Zero(12);
  const SolverResult newton = solver.solve(problem, settings, newton_r);
  settings.solver = ContactSolverType::automatic;
  Eigen::VectorXd r = Eigen::VectorXd::Zero(12);
  const SolverResult result = solver.solve(problem, settings, r);
  const auto nsgs = oracle.solve(500 /* SICONOS_FRICTION_3D_NSGS */, 1e-10, 10000);
  std::printf("Newton: %d it, residual %.3e m/s; auto: %d it (%s@%d, finished by %s), residual "
              "%.3e m/s, Siconos error %.3e; Siconos NSGS error %.3e\n",
              newton.iterations, newton.residual, result.iterations,
              to_string(result.switch_reason), result.switch_iteration,
              to_string(result.finished_by), result.residual, oracle.error(r), nsgs.error);
  EXPECT_GT(newton.residual, 1e-6); // why auto must not end with Newton here
  EXPECT_TRUE(result.converged());
  EXPECT_EQ(result.switch_reason, SwitchReason::slow);
  EXPECT_EQ(result.finished_by, ContactSolverType::gauss_seidel);
  EXPECT_LE(result.residual, settings.tolerance);
  EXPECT_LT(oracle.error(r), 1e-7); // Siconos's measure, relative to max(|q|, |u|, |r|)
  EXPECT_LT(oracle.error(r), 1e-3 * oracle.error(newton_r));
  EXPECT_NEAR(oracle.error(r), fc3d_error(source.dense_w(), source.q, source.mu, r), 1e-12);
  EXPECT_LT(nsgs.error, 1e-8);
}

// Newton's stall test (SolverSettings::newton_stall_iterations = 20) against the unstopped
// run's recorded residuals: on the rigid heel's problem Newton from zero wanders (0.022 m/s after
// 1000 iterations); with the test it must stop at the first iteration k at which 20 iterations
// have passed since the last halving of the residual (the chain of halvings starting from the
// residual of zero impulses), and return the iterate of the run cut at that iteration.
TEST(AutoRestart, NewtonStopsWhereItsResidualStopsHalving) {
  const WalkProblem walk("rigid_walk_collinear_heel.dat");
  const ContactProblem& problem = walk.problem;
  ContactSolver solver(problem.n_contacts, 0);
  solver.record_history(1000);
  SolverSettings settings;
  settings.tolerance = 1e-8;
  settings.max_iterations = 1000;
  settings.warm_start = false;
  settings.solver = ContactSolverType::newton;
  Eigen::VectorXd r = Eigen::VectorXd::Zero(9);
  const SolverResult full = solver.solve(problem, settings, r);
  const Eigen::VectorXd history = solver.history();
  ASSERT_EQ(history.size(), full.iterations);
  ASSERT_EQ(problem.normal_bias.head(3).norm(), 0.0); // v = W p + q: the start's is q
  double halved = ContactSolver::complementarity_residual(problem, Eigen::VectorXd::Zero(9),
                                                          problem.free_velocity.head(9));
  int halved_at = 0, expected = 0;
  for (int k = 1; k <= history.size() && expected == 0; ++k) {
    if (history[k - 1] < 0.5 * halved) {
      halved = history[k - 1];
      halved_at = k;
    } else if (k - halved_at >= 20) {
      expected = k;
    }
  }
  settings.newton_stall_iterations = 20;
  r.setZero();
  const SolverResult stopped = solver.solve(problem, settings, r);
  // The same iterate as the run cut at that iteration (both projected onto the cones).
  settings.newton_stall_iterations = 0;
  settings.max_iterations = std::max(expected, 1);
  Eigen::VectorXd r_cut = Eigen::VectorXd::Zero(9);
  const SolverResult cut = solver.solve(problem, settings, r_cut);
  std::printf("Newton from zero: %d iterations, residual %.3e m/s; with the stall test %d "
              "(expected %d), residual %.3e m/s (the run cut there: %.3e m/s)\n",
              full.iterations, full.residual, stopped.iterations, expected, stopped.residual,
              cut.residual);
  ASSERT_GT(expected, 20);
  EXPECT_EQ(stopped.iterations, expected);
  EXPECT_FALSE(stopped.converged());
  EXPECT_EQ(stopped.residual, cut.residual);
  EXPECT_EQ(r, r_cut);
}

// A compliant ankle's eight contacts in the flat walk (bench/robustness/forms_dt_theta.prm,
// dt 1 ms, theta 1/2: tests/contact/data/compliant_ankle_flat_walk_stall.dat, with the step's
// warm start). Gauss-Seidel is slow (its rate predicts > 100 sweeps), Newton from its iterate
// stalls near 3e-8 m/s for its whole half budget (2000 iterations), and the restart from zero
// converges in 7. With auto's stall test (auto_newton_stall_iterations = 20) the first attempt
// stops early and Newton from the warm start converges: a sixteenth of the iterations, the
// impulses of Newton alone from the warm start. W (24 x 24) is singular: the two solutions'
// impulses differ, their contact velocities W r + q do not.
TEST(AutoRestart, StopsNewtonFromGaussSeidelWhenItStalls) {
  const WalkProblem walk("compliant_ankle_flat_walk_stall.dat");
  const ContactProblem& problem = walk.problem;
  ASSERT_EQ(problem.n_contacts, 8);
  const Eigen::VectorXd warm = walk.warm_start();
  ContactSolver solver(problem.n_contacts, 0);
  SolverSettings settings;
  settings.tolerance = 1e-8; // m/s, as the walk scenes
  settings.max_iterations = 4000;
  settings.solver = ContactSolverType::automatic;
  settings.auto_newton_stall_iterations = 0;
  Eigen::VectorXd r_full = warm;
  const SolverResult full = solver.solve(problem, settings, r_full);
  settings.auto_newton_stall_iterations = SolverSettings().auto_newton_stall_iterations;
  Eigen::VectorXd r = warm;
  const SolverResult result = solver.solve(problem, settings, r);
  std::printf("auto without the stall test: %d iterations (%s after %d sweeps), residual %.3e "
              "m/s; with it: %d iterations, residual %.3e m/s; Siconos error %.3e; impulses "
              "differ by %.1e N s\n",
              full.iterations, to_string(full.switch_reason), full.switch_iteration, full.residual,
              result.iterations, result.residual, walk.oracle.error(r),
              (r - r_full).lpNorm<Eigen::Infinity>());
  ASSERT_TRUE(full.converged());
  ASSERT_TRUE(result.converged());
  EXPECT_EQ(result.finished_by, ContactSolverType::newton);
  EXPECT_GE(full.iterations, full.switch_iteration + settings.max_iterations / 2);
  EXPECT_LT(result.iterations, full.iterations / 10);
  EXPECT_LT(walk.oracle.error(r), 1e-7);
  EXPECT_LT(walk.oracle.error(r_full), 1e-7);
  settings.solver = ContactSolverType::newton;
  Eigen::VectorXd r_warm = warm;
  const SolverResult newton = solver.solve(problem, settings, r_warm);
  const Eigen::MatrixXd w = walk.source.dense_w();
  std::printf("Newton alone from the warm start: %d iterations; auto's impulses differ from it by "
              "%.1e N s; contact velocities of the two auto solutions differ by %.1e m/s\n",
              newton.iterations, (r - r_warm).lpNorm<Eigen::Infinity>(),
              (w * (r - r_full)).lpNorm<Eigen::Infinity>());
  EXPECT_TRUE(newton.converged());
  EXPECT_EQ((r - r_warm).lpNorm<Eigen::Infinity>(), 0.0);
  EXPECT_LT((w * (r - r_full)).lpNorm<Eigen::Infinity>(), 1e-8);
}

} // namespace
} // namespace plantar::contact::testing
