#pragma once
// Nonsmooth Gauss-Seidel (ContactSolverType::gauss_seidel, the baseline): sweeps over the
// contacts, each contact's 3x3 problem solved exactly (local_contact_solve.h) with the others
// fixed. The velocity is kept up to date through y = G^T p (rank m) and the patch products
// (DelassusProducts::rigid, patch_product), so a sweep costs O(n m + sum_j n_j^2); a
// compressed patch (CompliantPatch::compressed) keeps its product as an H-matrix product state
// instead (HierarchicalCompliance::ProductState): O(n_j (near rows + k log n_j)) per sweep.

#include "contact/iterative_solver.h"

#include <Eigen/Core>
#include <vector>

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

  // The product state of compressed patch @p j from @p p (sized at its first use).
  void start_compressed(const ContactProblem& problem, int j,
                        const Eigen::Ref<const Eigen::VectorXd>& p);
  // patch_product of every compressed patch from its state.
  void write_compressed(const ContactProblem& problem, DelassusProducts& products) const;

  int rigid_rank_ = 0;
  std::vector<HierarchicalCompliance::ProductState> compressed_; // per patch (compressed ones)
  Eigen::MatrixXd diag_blocks_;                                  // 3 x 3N, W_kk
  Eigen::MatrixXd diag_inverses_; // 3 x 3N, W_kk^-1 where has_inverse_ is 1 (local_inverse)
  Eigen::VectorXi has_inverse_;   // N: 1, 0 (singular), or -1 (W_kk not built in this call)
};

} // namespace plantar::contact
