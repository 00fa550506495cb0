#include "coupling/reduced_sole.h"

#include "coupling/condensed_sole.h"

#include <Eigen/Cholesky>
#include <Eigen/Eigenvalues>

#include <algorithm>
#include <cmath>
#include <sstream>
#include <stdexcept>
#include <string>

namespace plantar::coupling {

namespace {

/// Sizes of the patches of @p patch_of_node; throws on a negative value or an empty patch.
std::vector<int> patch_sizes_of(const std::vector<int>& patch_of_node) {
  if (patch_of_node.empty())
    throw std::invalid_argument("ReducedSole: no node (allowed >= 1)");
  const int p = *std::max_element(patch_of_node.begin(), patch_of_node.end()) + 1;
  std::vector<int> sizes(std::max(p, 0), 0);
  for (std::size_t k = 0; k < patch_of_node.size(); ++k) {
    if (patch_of_node[k] < 0)
      throw std::invalid_argument("ReducedSole: patch_of_node[" + std::to_string(k) +
                                  "] = " + std::to_string(patch_of_node[k]) + ", allowed >= 0");
    ++sizes[patch_of_node[k]];
  }
  for (int j = 0; j < p; ++j)
    if (sizes[j] == 0)
      throw std::invalid_argument("ReducedSole: patch " + std::to_string(j) + " has no node");
  return sizes;
}

/// Shares s_k = w_k / W_j(k) of @p patch_of_node's nodes (equal, 1 / n_j, for empty
/// @p weights); throws on a weight that is not positive and finite or of the wrong size.
Eigen::VectorXd shares_of(const std::vector<int>& patch_of_node, const Eigen::VectorXd& weights) {
  const std::vector<int> sizes = patch_sizes_of(patch_of_node);
  const Eigen::Index n = static_cast<Eigen::Index>(patch_of_node.size());
  if (weights.size() != 0 && weights.size() != n)
    throw std::invalid_argument("ReducedSole: " + std::to_string(weights.size()) +
                                " node weights for " + std::to_string(n) + " nodes");
  Eigen::VectorXd w = weights.size() == 0 ? Eigen::VectorXd::Ones(n) : weights;
  Eigen::VectorXd total = Eigen::VectorXd::Zero(static_cast<Eigen::Index>(sizes.size()));
  for (Eigen::Index k = 0; k < n; ++k) {
    if (!(w[k] > 0) || !std::isfinite(w[k]))
      throw std::invalid_argument("ReducedSole: node weight " + std::to_string(k) + " = " +
                                  std::to_string(w[k]) + ", allowed > 0 and finite");
    total[patch_of_node[k]] += w[k];
  }
  for (Eigen::Index k = 0; k < n; ++k)
    w[k] /= total[patch_of_node[k]];
  return w;
}

} // namespace

Eigen::VectorXd pressure_weights(const Eigen::VectorXd& areas) {
  if (areas.size() == 0 || !areas.allFinite() || !(areas.sum() > 0))
    throw std::invalid_argument("pressure_weights: the node areas must be finite with a positive "
                                "sum");
  return areas.cwiseMax(1e-3 * areas.mean());
}

void ReducedSole::set_patches(const Eigen::MatrixX3d& positions, int n_compliance_rows,
                              const Eigen::VectorXd& weights) {
  const int n = static_cast<int>(positions.rows());
  if (n == 0 || n_compliance_rows != 3 * n || static_cast<int>(patch_of_node_.size()) != n) {
    std::ostringstream msg;
    msg << "ReducedSole: " << n << " nodes (allowed >= 1), compliance of " << n_compliance_rows
        << " rows (expected " << 3 * n << "), patch_of_node size " << patch_of_node_.size()
        << " (expected " << n << ")";
    throw std::invalid_argument(msg.str());
  }
  patch_sizes_ = patch_sizes_of(patch_of_node_);
  shares_ = shares_of(patch_of_node_, weights);
  const int p = static_cast<int>(patch_sizes_.size());
  patch_positions_.setZero(p, 3);
  for (int k = 0; k < n; ++k)
    patch_positions_.row(patch_of_node_[k]) += shares_[k] * positions.row(k);
}

Eigen::SparseMatrix<double, Eigen::ColMajor, int>
ReducedSole::aggregation(const std::vector<int>& patch_of_node, const Eigen::VectorXd& weights) {
  const Eigen::VectorXd shares = shares_of(patch_of_node, weights);
  const int n = static_cast<int>(patch_of_node.size());
  const int p = *std::max_element(patch_of_node.begin(), patch_of_node.end()) + 1;
  std::vector<Eigen::Triplet<double, int>> entries;
  entries.reserve(3 * n);
  for (int k = 0; k < n; ++k)
    for (int d = 0; d < 3; ++d)
      entries.emplace_back(3 * k + d, 3 * patch_of_node[k] + d, shares[k]);
  Eigen::SparseMatrix<double, Eigen::ColMajor, int> a(3 * n, 3 * p);
  a.setFromTriplets(entries.begin(), entries.end());
  return a;
}

ReducedSole::ReducedSole(const CondensedSole& sole, const std::vector<int>& patch_of_node,
                         const Eigen::VectorXd& weights)
    : patch_of_node_(patch_of_node) {
  set_patches(sole.contact_positions(), 3 * sole.n_contacts(), weights);
  compliance_ = sole.projected_compliance(aggregation(patch_of_node_, weights));
}

ReducedSole::ReducedSole(const Eigen::MatrixX3d& positions, const Eigen::MatrixXd& compliance,
                         const std::vector<int>& patch_of_node, const Eigen::VectorXd& weights)
    : patch_of_node_(patch_of_node) {
  if (compliance.rows() != compliance.cols())
    throw std::invalid_argument("ReducedSole: compliance " + std::to_string(compliance.rows()) +
                                "x" + std::to_string(compliance.cols()) + " is not square");
  set_patches(positions, static_cast<int>(compliance.rows()), weights);
  const int n = n_nodes(), p = n_patches();

  // C A (3n x 3P): column block j sums the node columns of patch j times their shares s_k.
  Eigen::MatrixXd ca = Eigen::MatrixXd::Zero(3 * n, 3 * p);
  for (int k = 0; k < n; ++k) {
    const int j = patch_of_node[k];
    ca.middleCols<3>(3 * j) += shares_[k] * compliance.middleCols<3>(3 * k);
  }
  // A^T (C A): the same over rows.
  compliance_.setZero(3 * p, 3 * p);
  for (int k = 0; k < n; ++k) {
    const int j = patch_of_node[k];
    compliance_.middleRows<3>(3 * j) += shares_[k] * ca.middleRows<3>(3 * k);
  }
  compliance_ = 0.5 * (compliance_ + compliance_.transpose()).eval();
}

std::vector<int> ReducedSole::grid_patches(const Eigen::MatrixX3d& positions, int nx, int ny,
                                           GridSpacing spacing) {
  if (nx < 1 || ny < 1 || positions.rows() == 0) {
    std::ostringstream msg;
    msg << "ReducedSole::grid_patches: grid " << nx << " x " << ny << " (allowed >= 1 x 1), "
        << positions.rows() << " nodes (allowed >= 1)";
    throw std::invalid_argument(msg.str());
  }
  const Eigen::RowVector3d lo = positions.colwise().minCoeff();
  const Eigen::RowVector3d hi = positions.colwise().maxCoeff();
  // The cell of x in [a, b] split into m cells: uniform, or at the Chebyshev-Lobatto points
  // s_i = (1 - cos(pi i / m)) / 2, i.e. i = m acos(1 - 2 s) / pi for s = (x - a) / (b - a).
  auto cell = [spacing](double x, double a, double b, int m) {
    if (!(b > a))
      return 0;
    const double s = std::clamp((x - a) / (b - a), 0.0, 1.0);
    const double t = spacing == GridSpacing::uniform ? s : std::acos(1 - 2 * s) / M_PI;
    return std::clamp(static_cast<int>(std::floor(t * m)), 0, m - 1);
  };
  const int n = static_cast<int>(positions.rows());
  std::vector<int> cell_of_node(n), renumber(nx * ny, -1), patch(n);
  for (int k = 0; k < n; ++k)
    cell_of_node[k] =
        cell(positions(k, 0), lo[0], hi[0], nx) * ny + cell(positions(k, 1), lo[1], hi[1], ny);
  int next = 0;
  for (int k = 0; k < n; ++k) {
    int& id = renumber[cell_of_node[k]];
    if (id < 0)
      id = next++;
    patch[k] = id;
  }
  return patch;
}

Eigen::Matrix<double, 6, 6> rigid_motion_stiffness(const Eigen::MatrixX3d& positions,
                                                   const Eigen::MatrixXd& compliance,
                                                   const Eigen::Vector3d& origin) {
  const int n = static_cast<int>(positions.rows());
  if (compliance.rows() != 3 * n || compliance.cols() != 3 * n)
    throw std::invalid_argument(
        "rigid_motion_stiffness: compliance " + std::to_string(compliance.rows()) + "x" +
        std::to_string(compliance.cols()) + ", expected " + std::to_string(3 * n) + " square");
  Eigen::MatrixXd r = Eigen::MatrixXd::Zero(3 * n, 6);
  for (int k = 0; k < n; ++k) {
    const Eigen::Vector3d d = positions.row(k).transpose() - origin;
    r.block<3, 3>(3 * k, 0).setIdentity();
    r.block<3, 3>(3 * k, 3) << 0, d.z(), -d.y(), -d.z(), 0, d.x(), d.y(), -d.x(), 0;
  }
  const Eigen::LDLT<Eigen::MatrixXd> ldlt(compliance);
  const Eigen::MatrixXd k = r.transpose() * ldlt.solve(r);
  return 0.5 * (k + k.transpose());
}

double reduction_error_estimate(const Eigen::Matrix<double, 6, 6>& k_full,
                                const ReducedSole& reduced, const Eigen::Vector3d& origin) {
  const int p = reduced.n_patches();
  Eigen::MatrixXd r = Eigen::MatrixXd::Zero(3 * p, 6);
  for (int j = 0; j < p; ++j) {
    const Eigen::Vector3d d = reduced.patch_positions().row(j).transpose() - origin;
    r.block<3, 3>(3 * j, 0).setIdentity();
    r.block<3, 3>(3 * j, 3) << 0, d.z(), -d.y(), -d.z(), 0, d.x(), d.y(), -d.x(), 0;
  }
  const Eigen::LDLT<Eigen::MatrixXd> ldlt(reduced.compliance());
  const Eigen::Matrix<double, 6, 6> k_r = r.transpose() * ldlt.solve(r);
  const Eigen::Matrix<double, 6, 1> scale = k_full.diagonal().cwiseSqrt().cwiseInverse();
  const Eigen::Matrix<double, 6, 6> gap = scale.asDiagonal() * (k_full - k_r) * scale.asDiagonal();
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix<double, 6, 6>> eigen(
      0.5 * (gap + gap.transpose()), Eigen::EigenvaluesOnly);
  return eigen.eigenvalues().cwiseAbs().maxCoeff();
}

namespace {

/// The loop of choose_reduction: @p reduce builds the reduced sole of a patch assignment.
template <class Reduce>
ReductionChoice choose_grid(const Eigen::MatrixX3d& positions,
                            const Eigen::Matrix<double, 6, 6>& k_full, double tolerance,
                            GridSpacing spacing, const Reduce& reduce) {
  if (!(tolerance > 0))
    throw std::invalid_argument("choose_reduction: tolerance " + std::to_string(tolerance) +
                                ", allowed > 0");
  const int n = static_cast<int>(positions.rows());
  const Eigen::Vector3d origin = positions.colwise().mean().transpose();
  for (int g = 1;; g *= 2) {
    const std::vector<int> patches = ReducedSole::grid_patches(positions, g, g, spacing);
    if (*std::max_element(patches.begin(), patches.end()) + 1 == n)
      break; // one node per patch: no reduction left
    const ReducedSole reduced = reduce(patches);
    const double estimate = reduction_error_estimate(k_full, reduced, origin);
    if (estimate <= tolerance)
      return {g, reduced.n_patches(), estimate, true};
  }
  return {0, n, 0.0, false};
}

} // namespace

ReductionChoice choose_reduction(const Eigen::MatrixX3d& positions,
                                 const Eigen::MatrixXd& compliance, double tolerance,
                                 GridSpacing spacing, const Eigen::VectorXd& weights) {
  const Eigen::Vector3d origin = positions.colwise().mean().transpose();
  const Eigen::Matrix<double, 6, 6> k_full = rigid_motion_stiffness(positions, compliance, origin);
  return choose_grid(positions, k_full, tolerance, spacing, [&](const std::vector<int>& patches) {
    return ReducedSole(positions, compliance, patches, weights);
  });
}

ReductionChoice choose_reduction(const CondensedSole& sole, double tolerance, GridSpacing spacing,
                                 const Eigen::VectorXd& weights) {
  return choose_grid(
      sole.contact_positions(), sole.rigid_motion_stiffness(), tolerance, spacing,
      [&](const std::vector<int>& patches) { return ReducedSole(sole, patches, weights); });
}

} // namespace plantar::coupling
