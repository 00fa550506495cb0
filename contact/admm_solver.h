#pragma once
// ADMM (ContactSolverType::admm; Carpentier et al. 2024; Tasora et al. 2021): with De Saxce's
// correction s(v) = mu ||v_t|| e_n fixed per iteration, split p = x (free) = z (in the
// cones), scaled dual u:
//   (W + (rho + eta) I) x = -(v_free + b e_n + s) + (rho + eta) z - rho u
//   z = P_K(x + u),  u = u + x - z,
// rho adapted from the ratio of primal ||x - z|| and dual ||z - z_prev|| residuals. The matrix
// is factorised with the low-rank structure (Woodbury): D = blockdiag(C_j/dt^2) + c I (patch
// blocks by Cholesky, rigid-only contacts scalar), S = I_m + G^T D^-1 G (Cholesky, m x m).
//
// The patch Cholesky factorisations use an in-place tiled algorithm whose Eigen kernel calls
// stay under Eigen's stack scratch limit (no allocation). A patch factor is reused by the next
// solve when the patch block and the shift rho + eta are unchanged (with warm_rho the next
// solve starts at the last rho), so in a time loop with constant dt and contact set the
// O(n^3) factorisation is rare.

#include "contact/iterative_solver.h"

#include <Eigen/Core>

namespace plantar::contact {

class AdmmSolver final : public IterativeSolver {
public:
  /// Memory ~ 144 max_contacts^2 bytes (the patch factor and its cached copy).
  void resize(int max_contacts, int rigid_rank) override;
  /// Starts from @p impulses (its own products: @p start is not used).
  SolverResult solve(const ContactProblem& problem, const SolverSettings& settings,
                     Eigen::Ref<Eigen::VectorXd> impulses, DelassusProducts& products,
                     StartProducts start, ResidualHistory& history) override;
  long n_patch_factorizations() const override { return n_patch_factorizations_; }

private:
  bool factorize(const ContactProblem& problem, const DelassusProducts& products, double shift);
  // x = (W + shift I)^-1 rhs by the last factorisation.
  void solve_shifted(const ContactProblem& problem, const DelassusProducts& products,
                     const Eigen::Ref<const Eigen::VectorXd>& rhs, Eigen::Ref<Eigen::VectorXd> x);

  int rigid_rank_ = 0;
  Eigen::VectorXd x_, z_, z_prev_, dual_, rhs_; // 3N each
  Eigen::MatrixXd patch_factor_;                // 3N x 3N, Cholesky of patch blocks + cI
  Eigen::MatrixXd low_rank_;                    // 3N x m, H = D^-1 G
  Eigen::MatrixXd capacitance_;                 // m x m, Cholesky of I + G^T H
  Eigen::VectorXd rigid_work_;                  // m
  Eigen::VectorXd de_saxce_;                    // N, frozen mu ||v_t||
  double shift_ = 0.0;
  Eigen::MatrixXd patch_copy_;   // 3N x 3N, patch blocks of the last factorisation
  Eigen::VectorXi cached_first_; // per patch: first row and size of the cached factor
  Eigen::VectorXi cached_size_;
  int n_cached_patches_ = -1;
  double cached_shift_ = -1.0;
  double last_rho_ = 0.0; // final rho of the last solve (warm rho)
  long n_patch_factorizations_ = 0;
};

} // namespace plantar::contact
