#pragma once
// LU factorisation with partial pivoting of a dense square matrix, in place and without heap
// allocation (the semismooth Newton solver's linear solve).

#include <Eigen/Core>

namespace plantar::contact {

/// P A = L U in place over 64-column panels: each panel by an unblocked right-looking
/// elimination (row swaps over whole rows), then U12 by a unit-lower triangular solve and the
/// trailing update A22 -= L21 U12 by 64 x 64 x 64 products, so every Eigen kernel call keeps its
/// scratch on the stack (no allocation, as cholesky_in_place in admm_solver.cc).
/// @param a (n x n) overwritten by L (strict lower, unit diagonal) and U (upper).
/// @param pivots (>= n) row i was swapped with row pivots[i] at step i.
/// Returns false when a pivot is exactly zero (A singular); a and pivots are then partial.
bool lu_in_place(Eigen::Ref<Eigen::MatrixXd> a, Eigen::Ref<Eigen::VectorXi> pivots);

/// Solves A x = b with the factors of lu_in_place, in place on @p x (n). Does not allocate.
void lu_solve_in_place(const Eigen::Ref<const Eigen::MatrixXd>& lu,
                       const Eigen::Ref<const Eigen::VectorXi>& pivots,
                       Eigen::Ref<Eigen::VectorXd> x);

} // namespace plantar::contact
