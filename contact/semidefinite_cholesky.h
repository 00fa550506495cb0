#pragma once
// Cholesky factorisation of a symmetric positive semi-definite matrix that keeps its rank
// deficiency: A = L L^T with the columns of dependent pivots set to zero.

#include <Eigen/Core>

namespace plantar::contact {

/// Factors the symmetric positive semi-definite @p a (n x n, its lower triangle read) in place,
/// column by column: L(j, j) = sqrt(A(j, j) - sum_t L(j, t)^2), and column j is set to zero
/// (dependent) when that pivot is at or below @p relative_pivot times the largest diagonal
/// entry of A. On return the lower triangle holds L (A = L L^T up to the dropped pivots); the
/// strict upper triangle is left as it was. Returns the number of nonzero columns (the rank).
/// Does not allocate.
int semidefinite_cholesky(Eigen::Ref<Eigen::MatrixXd> a, double relative_pivot);

} // namespace plantar::contact
