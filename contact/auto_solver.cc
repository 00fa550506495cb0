#include "contact/auto_solver.h"

#include <algorithm>
#include <cmath>

namespace plantar::contact {

SolverResult AutoSolver::solve(const ContactProblem& problem, const SolverSettings& settings,
                               Eigen::Ref<Eigen::VectorXd> p, DelassusProducts& products,
                               StartProducts start, ResidualHistory& history) {
  const int n3 = 3 * problem.n_contacts;
  SolverSettings chunk = settings;
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
  // Gauss-Seidel's iterate, for Newton's third attempt and to resume from should Newton fail.
  const bool resumable = reason == SwitchReason::slow || reason == SwitchReason::stalled;
  switch_iterate_.head(n3) = p.head(n3);
  // Half of Newton's budget from Gauss-Seidel's iterate (stopped when it stalls), the other half
  // for a restart from zero; then, if the first was stopped, its rest without the stall test.
  const int half = std::max(1, settings.max_iterations / 2);
  chunk = settings;
  chunk.max_iterations = half;
  chunk.newton_stall_iterations = settings.auto_newton_stall_iterations;
  SolverResult result = newton_.solve(problem, chunk, p, products, StartProducts::build, history);
  int newton_iterations = result.iterations;
  if (!result.converged() && result.status != SolverStatus::non_finite &&
      newton_iterations < settings.max_iterations) {
    // Newton from Gauss-Seidel's iterate can stall where Newton from zero converges (redundant
    // contacts of compliant ankles): a restart from zero.
    const SolverResult first = result;
    const bool stopped = first.iterations < half;
    best_newton_.head(n3) = p.head(n3);
    chunk.newton_stall_iterations = 0;
    chunk.max_iterations = std::max(1, settings.max_iterations - half);
    p.head(n3).setZero();
    history.offset = sweeps + newton_iterations;
    result = newton_.solve(problem, chunk, p, products, StartProducts::build, history);
    newton_iterations += result.iterations;
    if (!result.converged() && !(result.residual < first.residual)) {
      restore(best_newton_); // the restart did no better: the first attempt
      result = first;
    }
    if (!result.converged() && result.status != SolverStatus::non_finite && stopped &&
        newton_iterations < settings.max_iterations) {
      // The restart failed too: the first attempt once more, without the stall test, with the
      // rest of the budget (slowly converging: a rigid heel's collinear contacts, test
      // contact_auto_restart); the best of the three is kept.
      const SolverResult stalled = result;
      best_newton_.head(n3) = p.head(n3);
      p.head(n3) = switch_iterate_.head(n3);
      chunk.max_iterations = settings.max_iterations - newton_iterations;
      history.offset = sweeps + newton_iterations;
      result = newton_.solve(problem, chunk, p, products, StartProducts::build, history);
      newton_iterations += result.iterations;
      if (!result.converged() && !(result.residual < stalled.residual)) {
        restore(best_newton_);
        result = stalled;
      }
    }
  }
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
