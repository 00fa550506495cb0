#pragma once
// Inner kernels of the Gauss-Seidel sweep over a dense compliance block.

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

} // namespace plantar::coupling
