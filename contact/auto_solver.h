#pragma once
// The automatic choice (ContactSolverType::automatic): Gauss-Seidel from the warm start, its
// rate measured every settings.auto_check_interval sweeps over the last five intervals (GS's
// residual is not monotone) as
//   rate = (r_end / r_start)^(1 / sweeps)   (residual ratio per sweep over the window);
// GS goes on while rate < 1 ("stalled" otherwise) and the predicted further sweeps s = log(tol /
// r_end) / log(rate) are at most settings.auto_switch_sweeps or cost less than
// settings.auto_newton_iterations Newton iterations, by operation counts:
//   sweep  ~ 2 nnz(W rows) + 200 n     (general W: its entries; G G^T + patches: 12 n m +
//                                       18 sum_j n_j^2),
//   Newton ~ SemismoothNewtonSolver::iteration_cost (its linear solve's factorisation, all
//            contacts active: (2/3) (3n)^3 dense, the Woodbury count, 54 x the stored blocks of
//            W for the sparse LU).
// Otherwise (or at max_iterations sweeps, or on non-finite values) semismooth Newton takes over
// from GS's iterate with its own budget of max_iterations. The result says which solver
// finished, why and when it switched (SolverResult::finished_by, switch_reason,
// switch_iteration, switch_rate); iterations counts GS sweeps plus Newton iterations.
//
// Newton from Gauss-Seidel's iterate has half of Newton's budget and stops early when it stalls
// (settings.auto_newton_stall_iterations iterations without halving its residual); stopped so,
// Newton runs from the warm start (when settings.warm_start and it is not zero) with the stall
// test and the rest of that half. If neither converged, Newton restarts from zero with the other
// half, and the better of the two attempts
// (by residual) is kept. If the first attempt was stopped early and the restart failed too,
// Newton restarts from zero with rho_k 10 x larger (SolverSettings::newton_rho_scale; half the
// budget left; the walks' redundant rigid contacts converge there in tens of iterations), then
// the first attempt runs once more without the stall test with the rest (the attempt as it was
// before the stall test), and the best of the attempts is kept.
// When neither converged after a slow or stalled Gauss-Seidel, Gauss-Seidel resumes from its
// iterate at the switch with the rest of its own budget (max_iterations - sweeps), and the
// better of the two is returned (finished_by says which; iterations counts all three phases).
//
// It runs the facade's own GaussSeidelSolver and SemismoothNewtonSolver; its own workspace is
// three sets of impulses (3 max_contacts each). solve() allocates nothing.

#include "contact/gauss_seidel_solver.h"
#include "contact/iterative_solver.h"
#include "contact/semismooth_newton_solver.h"

namespace plantar::contact {

class AutoSolver final : public IterativeSolver {
public:
  /// @p gauss_seidel and @p newton must outlive this and be resized with it.
  AutoSolver(GaussSeidelSolver& gauss_seidel, SemismoothNewtonSolver& newton)
      : gauss_seidel_(gauss_seidel), newton_(newton) {}
  void resize(int max_contacts, int /*rigid_rank*/) override {
    best_newton_.setZero(3 * max_contacts);
    switch_iterate_.setZero(3 * max_contacts);
    warm_iterate_.setZero(3 * max_contacts);
  }
  SolverResult solve(const ContactProblem& problem, const SolverSettings& settings,
                     Eigen::Ref<Eigen::VectorXd> impulses, DelassusProducts& products,
                     StartProducts start, ResidualHistory& history) override;

private:
  GaussSeidelSolver& gauss_seidel_;
  SemismoothNewtonSolver& newton_;
  Eigen::VectorXd best_newton_;    ///< the best Newton attempt's impulses so far, N s
  Eigen::VectorXd switch_iterate_; ///< Gauss-Seidel's impulses at the switch, N s
  Eigen::VectorXd warm_iterate_;   ///< the solve's start (warm start), N s
};

} // namespace plantar::contact
