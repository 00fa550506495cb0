#pragma once
// The symmetry check of a compliance (or any square matrix), written once.

#include <Eigen/Core>

namespace plantar::contact {

/// max_ij |A_ij - A_ji| / max_ij |A_ij| of the square matrix @p a (0 for a zero matrix).
/// Does not allocate.
double relative_asymmetry(const Eigen::Ref<const Eigen::MatrixXd>& a);

/// Throws std::invalid_argument "<where>: <what> is not symmetric (relative asymmetry X >
/// tolerance)" when relative_asymmetry(a) > @p tolerance (default 1e-9).
void check_symmetric(const Eigen::Ref<const Eigen::MatrixXd>& a, const char* where,
                     const char* what, double tolerance = 1e-9);

} // namespace plantar::contact
