#pragma once
// Inner kernels over dense compliance blocks and the kept inverse of their active part
// (Gauss-Seidel sweep, direct solve).

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

/// U = H B for a symmetric H held in its lower triangle and three columns B (one pass over
/// the triangle for all three).
/// @param h lower triangle of H (n x n, column-major, @p stride between columns; the upper
/// part is not read). @param b the three columns of B (each n long, @p b_stride apart). @param u
/// the three columns of U (@p u_stride apart, overwritten; must not overlap H or B). Same CPU
/// dispatch as add_three_columns.
void symmetric_lower_times_three(const double* h, Eigen::Index stride, Eigen::Index n,
                                 const double* b, Eigen::Index b_stride, double* u,
                                 Eigen::Index u_stride);

} // namespace plantar::coupling
