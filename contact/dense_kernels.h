#pragma once
// Inner kernels over dense compliance blocks and their factors (Gauss-Seidel sweep, direct
// solve).

#include <Eigen/Core>

namespace plantar::contact {

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

/// Solves L x = b in place (forward substitution, four columns of L at a time: their 4 x 4
/// triangle, then one update of the rows below). @param l as in solve_lower_three;
/// @param b (n) overwritten by x. Same CPU dispatch as add_three_columns.
void solve_lower(const double* l, Eigen::Index stride, Eigen::Index n, double* b);

/// Solves L^T x = b in place (back substitution, four columns of L at a time: their dot
/// products with the x already known, contiguous in column-major storage, then their 4 x 4
/// triangle). @param l as in solve_lower_three; @param b (n) overwritten by x. Same CPU
/// dispatch as add_three_columns.
void solve_lower_transposed(const double* l, Eigen::Index stride, Eigen::Index n, double* b);

/// Natural-map residuals of @p n contacts (coulomb_cone.h, contact_residual), in one loop the
/// compiler can vectorise:
///   r_k = || p_k - P_K(p_k - eta_k s_k) || / eta_k,  s_k = v_k + (b_k + mu_k ||v_k,t||) e_n.
/// @param p, @param v impulses (N s) and velocities (m/s), 3 n, contact frames (n, t1, t2).
/// @param bias b (n, m/s), @param mu friction (n, >= 0), @param eta (n, > 0, N s per m/s).
/// @param r (n) the residuals, m/s. Returns max_k r_k, NaN when any r_k is NaN.
double contact_residuals(Eigen::Index n, const double* p, const double* v, const double* bias,
                         const double* mu, const double* eta, double* r);

} // namespace plantar::contact
