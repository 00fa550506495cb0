#include "coupling/reduced_sole.h"

#include <Eigen/Cholesky>
#include <Eigen/Eigenvalues>

#include <algorithm>
#include <cmath>
#include <sstream>
#include <stdexcept>
#include <string>

namespace plantar::coupling {

ReducedSole::ReducedSole(const Eigen::MatrixX3d& positions, const Eigen::MatrixXd& compliance,
                         const std::vector<int>& patch_of_node)
    : patch_of_node_(patch_of_node) {
  const int n = static_cast<int>(positions.rows());
  if (n == 0 || compliance.rows() != 3 * n || compliance.cols() != 3 * n ||
      static_cast<int>(patch_of_node.size()) != n) {
    std::ostringstream msg;
    msg << "ReducedSole: " << n << " nodes (allowed >= 1), compliance " << compliance.rows() << "x"
        << compliance.cols() << " (expected " << 3 * n << " square), patch_of_node size "
        << patch_of_node.size() << " (expected " << n << ")";
    throw std::invalid_argument(msg.str());
  }
  const int p = *std::max_element(patch_of_node.begin(), patch_of_node.end()) + 1;
  patch_sizes_.assign(p, 0);
  for (int k = 0; k < n; ++k) {
    if (patch_of_node[k] < 0)
      throw std::invalid_argument("ReducedSole: patch_of_node[" + std::to_string(k) +
                                  "] = " + std::to_string(patch_of_node[k]) + ", allowed >= 0");
    ++patch_sizes_[patch_of_node[k]];
  }
  for (int j = 0; j < p; ++j)
    if (patch_sizes_[j] == 0)
      throw std::invalid_argument("ReducedSole: patch " + std::to_string(j) + " has no node");

  patch_positions_.setZero(p, 3);
  for (int k = 0; k < n; ++k)
    patch_positions_.row(patch_of_node[k]) += positions.row(k) / patch_sizes_[patch_of_node[k]];

  // C A (3n x 3P): column block j sums the node columns of patch j, divided by n_j.
  Eigen::MatrixXd ca = Eigen::MatrixXd::Zero(3 * n, 3 * p);
  for (int k = 0; k < n; ++k) {
    const int j = patch_of_node[k];
    ca.middleCols<3>(3 * j) += compliance.middleCols<3>(3 * k) / patch_sizes_[j];
  }
  // A^T (C A): the same over rows.
  compliance_.setZero(3 * p, 3 * p);
  for (int k = 0; k < n; ++k) {
    const int j = patch_of_node[k];
    compliance_.middleRows<3>(3 * j) += ca.middleRows<3>(3 * k) / patch_sizes_[j];
  }
  compliance_ = 0.5 * (compliance_ + compliance_.transpose()).eval();
}

std::vector<int> ReducedSole::grid_patches(const Eigen::MatrixX3d& positions, int nx, int ny) {
  if (nx < 1 || ny < 1 || positions.rows() == 0) {
    std::ostringstream msg;
    msg << "ReducedSole::grid_patches: grid " << nx << " x " << ny << " (allowed >= 1 x 1), "
        << positions.rows() << " nodes (allowed >= 1)";
    throw std::invalid_argument(msg.str());
  }
  const Eigen::RowVector3d lo = positions.colwise().minCoeff();
  const Eigen::RowVector3d hi = positions.colwise().maxCoeff();
  auto cell = [](double x, double a, double b, int m) {
    if (!(b > a))
      return 0;
    return std::clamp(static_cast<int>(std::floor((x - a) / (b - a) * m)), 0, m - 1);
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

ReductionChoice choose_reduction(const Eigen::MatrixX3d& positions,
                                 const Eigen::MatrixXd& compliance, double tolerance) {
  if (!(tolerance > 0))
    throw std::invalid_argument("choose_reduction: tolerance " + std::to_string(tolerance) +
                                ", allowed > 0");
  const int n = static_cast<int>(positions.rows());
  const Eigen::Vector3d origin = positions.colwise().mean().transpose();
  const Eigen::Matrix<double, 6, 6> k_full = rigid_motion_stiffness(positions, compliance, origin);
  for (int g = 1;; g *= 2) {
    const ReducedSole reduced(positions, compliance, ReducedSole::grid_patches(positions, g, g));
    if (reduced.n_patches() == n)
      break; // one node per patch: no reduction left

    const double estimate = reduction_error_estimate(k_full, reduced, origin);
    if (estimate <= tolerance)
      return {g, reduced.n_patches(), estimate, true};
  }
  return {0, n, 0.0, false};
}

} // namespace plantar::coupling
