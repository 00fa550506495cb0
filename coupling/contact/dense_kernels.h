#pragma once
// Inner kernels over dense compliance blocks and their factors (Gauss-Seidel sweep, direct
// solve).

#include <Eigen/Core>

namespace plantar::coupling {

/// w += C(:, c:c+3) d: three adjacent columns of a column-major block times a 3-vector
/// (the column update of one contact, m/s).
/// @param columns first of the three columns (each @p rows long, @p stride apart), m/(N s^2).
/// @param d (3) impulse change in the patch frame, N s.
/// @param w (rows) patch-frame velocities, m/s. Built for AVX2/FMA when the CPU has them
/// (chosen at load time on x86-64 with GCC), else for the baseline.
void add_three_columns(const double* columns, Eigen::Index stride, Eigen::Index rows,
                       const double* d, double* w);

/// Solves L X = B in place for three right-hand sides (forward substitution by columns of L:
/// one pass over the triangle for all three, against three for three single solves).
/// @param l lower triangle of L (n x n, column-major, @p stride between columns, nonzero
/// diagonal). @param b the three columns of B (each n long, @p b_stride apart), overwritten
/// by X. Same CPU dispatch as add_three_columns.
void solve_lower_three(const double* l, Eigen::Index stride, Eigen::Index n, double* b,
                       Eigen::Index b_stride);

} // namespace plantar::coupling
