#pragma once
// Nonsmooth Gauss-Seidel (ContactSolverType::gauss_seidel, the baseline): sweeps over the
// contacts, each contact's 3x3 problem solved exactly (local_contact_solve.h) with the others
// fixed. The velocity is kept up to date through y = G^T p (rank m) and the patch products
// (DelassusProducts::rigid, patch_product), so a sweep costs O(n m + sum_j n_j^2).

#include "contact/iterative_solver.h"

#include <Eigen/Core>

namespace plantar::contact {

class GaussSeidelSolver final : public IterativeSolver {
public:
  void resize(int max_contacts, int rigid_rank) override;
  /// With StartProducts::held and SolverSettings::sweep_skip > 0 a sweep visits only the
  /// contacts whose residual at the last check was above the skip, W_kk built at first need.
  SolverResult solve(const ContactProblem& problem, const SolverSettings& settings,
                     Eigen::Ref<Eigen::VectorXd> impulses, DelassusProducts& products,
                     StartProducts start, ResidualHistory& history) override;

private:
  // products.rigid = G^T p and products.patch_product of the start @p p (from
  // CompliantPatch::warm_product when the caller holds it and settings.warm_start).
  void start_iteration(const ContactProblem& problem, const SolverSettings& settings,
                       const Eigen::Ref<const Eigen::VectorXd>& p, DelassusProducts& products);

  int rigid_rank_ = 0;
  Eigen::MatrixXd diag_blocks_;   // 3 x 3N, W_kk
  Eigen::MatrixXd diag_inverses_; // 3 x 3N, W_kk^-1 where has_inverse_ is 1 (local_inverse)
  Eigen::VectorXi has_inverse_;   // N: 1, 0 (singular), or -1 (W_kk not built in this call)
};

} // namespace plantar::contact
