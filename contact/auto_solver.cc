#include "contact/auto_solver.h"

#include <algorithm>
#include <cmath>

namespace plantar::contact {

namespace {
/// rho of the retry from zero, relative to rho_k = 3 / trace(W_kk) (auto_solver.h).
constexpr double kRhoRetryScale = 10.0;
} // namespace

SolverResult AutoSolver::solve(const ContactProblem& problem, const SolverSettings& settings,
                               Eigen::Ref<Eigen::VectorXd> p, DelassusProducts& products,
                               StartProducts start, ResidualHistory& history) {
  const int n3 = 3 * problem.n_contacts;
  SolverSettings chunk = settings;
  warm_iterate_.head(n3) = p.head(n3); // the warm start, for a Newton attempt from it
  const bool warm = settings.warm_start && p.head(n3).any();
  // The residual at the start (GS reports only its sweeps'); G^T p is unchanged by this, so
  // held products stay valid.
  products.compute_velocity(problem, p);
  double before = products.residual(problem, p, products.velocity);
  // Operation counts of one GS sweep and one Newton iteration (auto_solver.h).
  const double n = problem.n_contacts;
  double sweep_cost = 200.0 * n + 12.0 * n * problem.rigid_rank();
  for (const CompliantPatch& patch : problem.patches)
    sweep_cost += 18.0 * patch.n_contacts * patch.n_contacts;
  if (!problem.general.empty())
    sweep_cost += 2.0 * static_cast<double>(problem.general.nonzeros());
  const double newton_cost =
      SemismoothNewtonSolver::iteration_cost(problem, settings.newton_linear_solve);
  const double sweeps_worth_newton = settings.auto_newton_iterations * newton_cost / sweep_cost;
  constexpr int kWindow = 5;
  double window_residual[kWindow] = {};
  int window_sweeps[kWindow] = {};
  int n_chunks = 0;
  SolverResult gs;
  int sweeps = 0;
  SwitchReason reason = SwitchReason::none;
  double rate = 0.0;
  if (!(before <= settings.tolerance)) {
    while (true) {
      chunk.max_iterations =
          std::min(settings.auto_check_interval, settings.max_iterations - sweeps);
      history.offset = sweeps;
      gs = gauss_seidel_.solve(problem, chunk, p, products, start, history);
      start = StartProducts::build;
      chunk.warm_start = false; // CompliantPatch::warm_product is of the first start only
      sweeps += gs.iterations;
      if (gs.status == SolverStatus::converged)
        break;
      if (gs.status == SolverStatus::non_finite || !p.head(n3).allFinite()) {
        reason = SwitchReason::failed;
        p.head(n3).setZero();
        break;
      }
      // The rate over the last kWindow intervals (GS's residual is not monotone).
      const double after = gs.residual;
      window_residual[n_chunks % kWindow] = before;
      window_sweeps[n_chunks % kWindow] = sweeps - gs.iterations;
      ++n_chunks;
      const int oldest = n_chunks < kWindow ? 0 : n_chunks % kWindow;
      const int span = sweeps - window_sweeps[oldest];
      rate = span > 0 ? std::pow(after / window_residual[oldest], 1.0 / span) : 1.0;
      if (!(rate < 1.0)) {
        reason = SwitchReason::stalled;
        break;
      }
      const double predicted = std::log(settings.tolerance / after) / std::log(rate);
      if (predicted > settings.auto_switch_sweeps && predicted > sweeps_worth_newton) {
        reason = SwitchReason::slow;
        break;
      }
      if (sweeps >= settings.max_iterations) {
        reason = SwitchReason::budget;
        break;
      }
      before = after;
    }
  } else {
    gs.status = SolverStatus::converged;
    gs.residual = before;
  }
  history.offset = 0;
  if (reason == SwitchReason::none) {
    gs.iterations = sweeps;
    gs.finished_by = ContactSolverType::gauss_seidel;
    return gs;
  }
  history.offset = sweeps;
  // Impulses saved earlier, back in p with their products rebuilt (for ContactSolver's
  // velocity and patch_product()).
  const auto restore = [&](const Eigen::VectorXd& saved) {
    p.head(n3) = saved.head(n3);
    products.compute_velocity(problem, p);
    for (const CompliantPatch& patch : problem.patches)
      products.compute_patch_product(patch, p);
  };
  // Gauss-Seidel's iterate, for Newton's attempts from it and to resume from should Newton fail.
  const bool resumable = reason == SwitchReason::slow || reason == SwitchReason::stalled;
  switch_iterate_.head(n3) = p.head(n3);
  // Newton attempts (auto_solver.h), each from Gauss-Seidel's iterate, the warm start or zero;
  // the best so far (by residual) is kept in best_newton_.
  int newton_iterations = 0;
  SolverResult result;
  bool last_is_best = true, any_attempt = false;
  enum class From { zero, switch_iterate, warm_start };
  const auto attempt = [&](From from, int budget, int stall, double rho_scale) {
    if (from == From::switch_iterate)
      p.head(n3) = switch_iterate_.head(n3);
    else if (from == From::warm_start)
      p.head(n3) = warm_iterate_.head(n3);
    else
      p.head(n3).setZero();
    chunk = settings;
    chunk.max_iterations = std::max(1, budget);
    chunk.newton_stall_iterations = stall;
    chunk.newton_rho_scale = settings.newton_rho_scale * rho_scale;
    history.offset = sweeps + newton_iterations;
    const SolverResult r =
        newton_.solve(problem, chunk, p, products, StartProducts::build, history);
    newton_iterations += r.iterations;
    last_is_best = !any_attempt || r.converged() || r.residual < result.residual;
    any_attempt = true;
    if (last_is_best) {
      result = r;
      best_newton_.head(n3) = p.head(n3);
    }
    return r;
  };
  const auto go_on = [&](const SolverResult& last) {
    return !result.converged() && last.status != SolverStatus::non_finite &&
           newton_iterations < settings.max_iterations;
  };
  const int half = std::max(1, settings.max_iterations / 2);
  const int stall = settings.auto_newton_stall_iterations;
  const SolverResult first = attempt(From::switch_iterate, half, stall, 1.0);
  const bool stopped = first.iterations < half;
  // Stopped early, Newton from the warm start (the step before's impulses) with the stall test
  // and the rest of the first half: on redundant rigid contacts (a compliant ankle's 9 x 9 grid)
  // it can converge where Newton from Gauss-Seidel's iterate and from zero stall.
  SolverResult from_warm = first;
  if (stopped && warm && go_on(first))
    from_warm = attempt(From::warm_start, half - first.iterations, stall, 1.0);
  // Newton from Gauss-Seidel's iterate can stall where Newton from zero converges (redundant
  // contacts of compliant ankles): a restart from zero with the other half.
  if (go_on(from_warm)) {
    const SolverResult restart = attempt(From::zero, settings.max_iterations - half, 0, 1.0);
    // Both failed after a stopped first attempt: Newton from zero with rho 10 x larger (the
    // walks' redundant rigid contacts converge there in tens of iterations where rho x 1 needs
    // thousands) with half the budget left; then the first attempt without the stall test.
    if (stopped && go_on(restart)) {
      const SolverResult stiff =
          attempt(From::zero, (settings.max_iterations - newton_iterations) / 2, 0, kRhoRetryScale);
      if (go_on(stiff))
        attempt(From::switch_iterate, settings.max_iterations - newton_iterations, 0, 1.0);
    }
  }
  if (!last_is_best)
    restore(best_newton_);
  result.iterations = newton_iterations;
  result.finished_by = ContactSolverType::newton;
  if (!result.converged() && resumable && sweeps < settings.max_iterations) {
    // Newton failed where it was predicted to be faster (a singular Newton matrix: redundant
    // contacts at an edge): Gauss-Seidel resumes from its own iterate with the rest of its
    // budget, and the better of the two is kept.
    const SolverResult newton = result;
    best_newton_.head(n3) = p.head(n3);
    p.head(n3) = switch_iterate_.head(n3);
    chunk = settings;
    chunk.warm_start = false;
    chunk.max_iterations = settings.max_iterations - sweeps;
    history.offset = sweeps + newton.iterations;
    SolverResult resumed =
        gauss_seidel_.solve(problem, chunk, p, products, StartProducts::build, history);
    if (resumed.converged() || resumed.residual < newton.residual) {
      resumed.finished_by = ContactSolverType::gauss_seidel;
      resumed.iterations += newton.iterations;
      result = resumed;
    } else {
      restore(best_newton_);
      result = newton;
      result.iterations += resumed.iterations;
    }
  }
  history.offset = 0;
  result.switch_reason = reason;
  result.switch_iteration = sweeps;
  result.switch_rate = rate;
  result.n_local_solves = gs.n_local_solves;
  result.iterations += sweeps;
  return result;
}

} // namespace plantar::contact
