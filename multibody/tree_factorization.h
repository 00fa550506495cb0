#pragma once
// The joint-space inertia factored along the kinematic tree (Featherstone 2005, "Efficient
// factorization of the joint-space inertia matrix for branched kinematic trees", the LTDL
// algorithm; Pinocchio's cholesky::decompose).
//
// For a matrix A (nv x nv, symmetric positive definite) with the sparsity of a tree's mass
// matrix, A_ij = 0 unless dof j is an ancestor of dof i or i of j (M(q) plus any diagonal,
// e.g. M + theta dt D + theta^2 dt^2 K):
//   A = L^T D L,   L unit lower triangular, L_ij != 0 only for j an ancestor of i, D diagonal,
// computed in place without fill-in: sum over dofs of depth^2 operations instead of nv^3 / 6.
// With U = L^T D^1/2 (upper triangular), A = U U^T; the contact rows use the half solves
// U^-1 x = D^-1/2 L^-T x and U^-T x = L^-1 D^-1/2 x, which visit only the ancestors of the
// nonzeros of x (a body's Jacobian J_b^T is nonzero on its ancestors' dofs only).
//
// Dof tree: a joint's dofs form a chain (the free base's 6 in order, its block dense), the
// first one's parent the last dof of the parent joint, -1 for a joint on the world.

#include "multibody/model.h"

#include <Eigen/Core>
#include <vector>

namespace plantar::multibody {

class TreeFactorization {
public:
  TreeFactorization() = default;
  /// The dof tree of @p model (allocates nv x nv once).
  explicit TreeFactorization(const Model& model);

  /// Factors @p a (nv x nv, symmetric with the tree's sparsity: only A_jk for j = k or an
  /// ancestor of k is read, in the upper triangle) as L^T D L.
  /// Returns false, leaving the factor invalid, when a pivot d_i is not positive (A not positive
  /// definite). Allocates nothing.
  bool compute(const Eigen::Ref<const Eigen::MatrixXd>& a);

  /// x <- A^-1 x, @p x nv x k.
  void solve_in_place(Eigen::Ref<Eigen::MatrixXd> x) const;
  /// x <- U^-1 x = D^-1/2 L^-T x (A = U U^T), @p x nv x k; rows of x that are zero on a dof
  /// and all its descendants stay zero and cost nothing.
  void half_solve_in_place(Eigen::Ref<Eigen::MatrixXd> x) const;
  /// x <- U^-T x = L^-1 D^-1/2 x, @p x nv x k.
  void half_solve_transpose_in_place(Eigen::Ref<Eigen::MatrixXd> x) const;

  int size() const { return static_cast<int>(parent_.size()); }
  /// Parent dof of dof @p i (-1: a root dof).
  int parent(int i) const { return parent_[i]; }
  /// The factor: D on the diagonal, L's strict lower triangle below it (the rest unused).
  const Eigen::MatrixXd& factor() const { return factor_; }

private:
  std::vector<int> parent_; // parent dof, -1 for a root
  Eigen::MatrixXd factor_;  // L (strict lower) and D (diagonal)
  Eigen::VectorXd sqrt_d_;  // D^1/2
};

} // namespace plantar::multibody
