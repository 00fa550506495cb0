#include "coupling/reduced_sole.h"

#include "coupling/condensed_sole.h"

#include <Eigen/Cholesky>
#include <Eigen/Eigenvalues>

#include <algorithm>
#include <cmath>
#include <sstream>
#include <stdexcept>
#include <string>
#include <utility>

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

void ReducedSole::set_patches(const Eigen::MatrixX3d& positions, int n_compliance_rows) {
  const int n = static_cast<int>(positions.rows());
  if (n == 0 || n_compliance_rows != 3 * n || shares_.rows() != n) {
    std::ostringstream msg;
    msg << "ReducedSole: " << n << " nodes (allowed >= 1), compliance of " << n_compliance_rows
        << " rows (expected " << 3 * n << "), shares of " << shares_.rows() << " rows (expected "
        << n << ")";
    throw std::invalid_argument(msg.str());
  }
  const int p = n_patches();
  patch_sizes_.assign(p, 0);
  patch_positions_.setZero(p, 3);
  for (int j = 0; j < p; ++j) {
    double total = 0;
    for (ShareMatrix::InnerIterator it(shares_, j); it; ++it) {
      if (!(it.value() >= 0) || !std::isfinite(it.value()))
        throw std::invalid_argument("ReducedSole: share of node " + std::to_string(it.row()) +
                                    " in patch " + std::to_string(j) + " = " +
                                    std::to_string(it.value()) + ", allowed >= 0 and finite");
      total += it.value();
      patch_sizes_[j] += it.value() > 0 ? 1 : 0;
      patch_positions_.row(j) += it.value() * positions.row(it.row());
    }
    if (std::abs(total - 1.0) > 1e-12)
      throw std::invalid_argument("ReducedSole: the shares of patch " + std::to_string(j) +
                                  " sum to " + std::to_string(total) + ", allowed 1");
  }
}

ReducedSole::ShareMatrix ReducedSole::partition_shares(const std::vector<int>& patch_of_node,
                                                       const Eigen::VectorXd& weights) {
  const Eigen::VectorXd shares = shares_of(patch_of_node, weights);
  const int n = static_cast<int>(patch_of_node.size());
  const int p = *std::max_element(patch_of_node.begin(), patch_of_node.end()) + 1;
  std::vector<Eigen::Triplet<double, int>> entries;
  entries.reserve(n);
  for (int k = 0; k < n; ++k)
    entries.emplace_back(k, patch_of_node[k], shares[k]);
  ShareMatrix s(n, p);
  s.setFromTriplets(entries.begin(), entries.end());
  return s;
}

ReducedSole::ShareMatrix ReducedSole::aggregation(const ShareMatrix& shares) {
  std::vector<Eigen::Triplet<double, int>> entries;
  entries.reserve(3 * shares.nonZeros());
  for (int j = 0; j < shares.outerSize(); ++j)
    for (ShareMatrix::InnerIterator it(shares, j); it; ++it)
      for (int d = 0; d < 3; ++d)
        entries.emplace_back(3 * static_cast<int>(it.row()) + d, 3 * j + d, it.value());
  ShareMatrix a(3 * shares.rows(), 3 * shares.cols());
  a.setFromTriplets(entries.begin(), entries.end());
  return a;
}

ReducedSole::ShareMatrix ReducedSole::aggregation(const std::vector<int>& patch_of_node,
                                                  const Eigen::VectorXd& weights) {
  return aggregation(partition_shares(patch_of_node, weights));
}

ReducedSole::ReducedSole(const CondensedSole& sole, const ShareMatrix& shares) : shares_(shares) {
  set_patches(sole.contact_positions(), 3 * sole.n_contacts());
  compliance_ = sole.projected_compliance(aggregation(shares_));
}

ReducedSole::ReducedSole(const CondensedSole& sole, const std::vector<int>& patch_of_node,
                         const Eigen::VectorXd& weights)
    : ReducedSole(sole, partition_shares(patch_of_node, weights)) {}

ReducedSole::ReducedSole(const Eigen::MatrixX3d& positions, const Eigen::MatrixXd& compliance,
                         const ShareMatrix& shares)
    : shares_(shares) {
  if (compliance.rows() != compliance.cols())
    throw std::invalid_argument("ReducedSole: compliance " + std::to_string(compliance.rows()) +
                                "x" + std::to_string(compliance.cols()) + " is not square");
  set_patches(positions, static_cast<int>(compliance.rows()));
  const ShareMatrix a = aggregation(shares_);
  const Eigen::MatrixXd ca = compliance * a; // C A (3n x 3P)
  compliance_ = a.transpose() * ca;
  compliance_ = 0.5 * (compliance_ + compliance_.transpose()).eval();
}

ReducedSole::ReducedSole(const Eigen::MatrixX3d& positions, const Eigen::MatrixXd& compliance,
                         const std::vector<int>& patch_of_node, const Eigen::VectorXd& weights)
    : ReducedSole(positions, compliance, partition_shares(patch_of_node, weights)) {}

namespace {

/// Where x lies on [a, b] split into m cells (uniform or at the Chebyshev-Lobatto points
/// s_i = (1 - cos(pi i / m)) / 2): its cell, and its coordinate in that cell, in [0, 1].
struct GridAxis {
  double a, b;
  int m;
  GridSpacing spacing;
  double edge(int i) const {
    const double t = double(i) / m;
    return a + (b - a) * (spacing == GridSpacing::uniform ? t : (1 - std::cos(M_PI * t)) / 2);
  }
  std::pair<int, double> locate(double x) const {
    if (!(b > a))
      return {0, 0.0};
    const double s = std::clamp((x - a) / (b - a), 0.0, 1.0);
    const double t = spacing == GridSpacing::uniform ? s : std::acos(1 - 2 * s) / M_PI;
    const int i = std::clamp(static_cast<int>(std::floor(t * m)), 0, m - 1);
    const double lo = edge(i), hi = edge(i + 1);
    // A node on a vertex line up to gmsh's round-off (1e-9 of the cell) is on it exactly.
    const double u = std::clamp((x - lo) / (hi - lo), 0.0, 1.0);
    return {i, u < 1e-9 ? 0.0 : (u > 1 - 1e-9 ? 1.0 : u)};
  }
};

std::pair<GridAxis, GridAxis> grid_axes(const Eigen::MatrixX3d& positions, int nx, int ny,
                                        GridSpacing spacing, const char* caller) {
  if (nx < 1 || ny < 1 || positions.rows() == 0) {
    std::ostringstream msg;
    msg << "ReducedSole::" << caller << ": grid " << nx << " x " << ny << " (allowed >= 1 x 1), "
        << positions.rows() << " nodes (allowed >= 1)";
    throw std::invalid_argument(msg.str());
  }
  const Eigen::RowVector3d lo = positions.colwise().minCoeff();
  const Eigen::RowVector3d hi = positions.colwise().maxCoeff();
  return {GridAxis{lo[0], hi[0], nx, spacing}, GridAxis{lo[1], hi[1], ny, spacing}};
}

} // namespace

std::vector<int> ReducedSole::grid_patches(const Eigen::MatrixX3d& positions, int nx, int ny,
                                           GridSpacing spacing) {
  const auto [x_axis, y_axis] = grid_axes(positions, nx, ny, spacing, "grid_patches");
  const int n = static_cast<int>(positions.rows());
  std::vector<int> cell_of_node(n), renumber(nx * ny, -1), patch(n);
  for (int k = 0; k < n; ++k)
    cell_of_node[k] =
        x_axis.locate(positions(k, 0)).first * ny + y_axis.locate(positions(k, 1)).first;
  int next = 0;
  for (int k = 0; k < n; ++k) {
    int& id = renumber[cell_of_node[k]];
    if (id < 0)
      id = next++;
    patch[k] = id;
  }
  return patch;
}

ReducedSole::ShareMatrix ReducedSole::grid_shares(const Eigen::MatrixX3d& positions, int nx, int ny,
                                                  GridSpacing spacing, PatchBasis basis,
                                                  const Eigen::VectorXd& weights) {
  if (basis == PatchBasis::constant)
    return partition_shares(grid_patches(positions, nx, ny, spacing), weights);
  const auto [x_axis, y_axis] = grid_axes(positions, nx, ny, spacing, "grid_shares");
  const int n = static_cast<int>(positions.rows());
  if (weights.size() != 0 && weights.size() != n)
    throw std::invalid_argument("ReducedSole::grid_shares: " + std::to_string(weights.size()) +
                                " node weights for " + std::to_string(n) + " nodes");
  // phi_v(x_k) w_k for the four vertices of node k's cell, then each vertex's column scaled to
  // sum to 1; vertices whose hat covers no node (column sum 0) are dropped.
  const int n_vertices = (nx + 1) * (ny + 1);
  std::vector<Eigen::Triplet<double, int>> entries;
  entries.reserve(4 * n);
  Eigen::VectorXd total = Eigen::VectorXd::Zero(n_vertices);
  for (int k = 0; k < n; ++k) {
    const double w = weights.size() == 0 ? 1.0 : weights[k];
    if (!(w > 0) || !std::isfinite(w))
      throw std::invalid_argument("ReducedSole::grid_shares: node weight " + std::to_string(k) +
                                  " = " + std::to_string(w) + ", allowed > 0 and finite");
    const auto [i, s] = x_axis.locate(positions(k, 0));
    const auto [j, t] = y_axis.locate(positions(k, 1));
    const double hat[4] = {(1 - s) * (1 - t), s * (1 - t), (1 - s) * t, s * t};
    const int vertex[4] = {i * (ny + 1) + j, (i + 1) * (ny + 1) + j, i * (ny + 1) + j + 1,
                           (i + 1) * (ny + 1) + j + 1};
    for (int c = 0; c < 4; ++c)
      if (hat[c] > 0) {
        entries.emplace_back(k, vertex[c], hat[c] * w);
        total[vertex[c]] += hat[c] * w;
      }
  }
  std::vector<int> column(n_vertices, -1);
  int p = 0;
  for (int v = 0; v < n_vertices; ++v)
    if (total[v] > 0)
      column[v] = p++;
  for (auto& e : entries)
    e = Eigen::Triplet<double, int>(e.row(), column[e.col()], e.value() / total[e.col()]);
  ShareMatrix shares(n, p);
  shares.setFromTriplets(entries.begin(), entries.end());
  return shares;
}

Eigen::MatrixXd rigid_motion_map(const Eigen::MatrixX3d& positions, const Eigen::Vector3d& origin) {
  Eigen::MatrixXd r = Eigen::MatrixXd::Zero(3 * positions.rows(), 6);
  for (Eigen::Index k = 0; k < positions.rows(); ++k) {
    const Eigen::Vector3d d = positions.row(k).transpose() - origin;
    r.block<3, 3>(3 * k, 0).setIdentity();
    r.block<3, 3>(3 * k, 3) << 0, d.z(), -d.y(), -d.z(), 0, d.x(), d.y(), -d.x(), 0;
  }
  return r;
}

Eigen::MatrixXd rigid_motion_forces(const Eigen::MatrixX3d& positions,
                                    const Eigen::MatrixXd& compliance,
                                    const Eigen::Vector3d& origin) {
  const int n = static_cast<int>(positions.rows());
  if (compliance.rows() != 3 * n || compliance.cols() != 3 * n)
    throw std::invalid_argument(
        "rigid_motion_forces: compliance " + std::to_string(compliance.rows()) + "x" +
        std::to_string(compliance.cols()) + ", expected " + std::to_string(3 * n) + " square");
  return compliance.ldlt().solve(rigid_motion_map(positions, origin));
}

namespace {

/// R^T F (6 x 6), symmetrized: the stiffness of the rigid-motion forces @p forces (3n x 6) of
/// the points @p positions about @p origin.
Eigen::Matrix<double, 6, 6> stiffness_of_forces(const Eigen::MatrixX3d& positions,
                                                const Eigen::MatrixXd& forces,
                                                const Eigen::Vector3d& origin) {
  const Eigen::MatrixXd k = rigid_motion_map(positions, origin).transpose() * forces;
  return 0.5 * (k + k.transpose());
}

} // namespace

Eigen::Matrix<double, 6, 6> rigid_motion_stiffness(const Eigen::MatrixX3d& positions,
                                                   const Eigen::MatrixXd& compliance,
                                                   const Eigen::Vector3d& origin) {
  return stiffness_of_forces(positions, rigid_motion_forces(positions, compliance, origin), origin);
}

namespace {

/// C_r^-1 R_r (3P x 6): the patch forces of @p reduced holding its face in each rigid motion
/// about @p origin.
Eigen::MatrixXd reduced_rigid_forces(const ReducedSole& reduced, const Eigen::Vector3d& origin) {
  return reduced.compliance().ldlt().solve(rigid_motion_map(reduced.patch_positions(), origin));
}

/// reduction_error_estimate from the reduced sole's @p patch_forces (reduced_rigid_forces).
double stiffness_estimate(const Eigen::Matrix<double, 6, 6>& k_full, const ReducedSole& reduced,
                          const Eigen::MatrixXd& patch_forces, const Eigen::Vector3d& origin) {
  const Eigen::Matrix<double, 6, 6> k_r =
      rigid_motion_map(reduced.patch_positions(), origin).transpose() * patch_forces;
  const Eigen::Matrix<double, 6, 1> scale = k_full.diagonal().cwiseSqrt().cwiseInverse();
  const Eigen::Matrix<double, 6, 6> gap = scale.asDiagonal() * (k_full - k_r) * scale.asDiagonal();
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix<double, 6, 6>> eigen(
      0.5 * (gap + gap.transpose()), Eigen::EigenvaluesOnly);
  return eigen.eigenvalues().cwiseAbs().maxCoeff();
}

/// pressure_error_estimate from the reduced sole's @p patch_forces (reduced_rigid_forces).
double pressure_estimate(const Eigen::MatrixXd& forces_full, const ReducedSole& reduced,
                         const Eigen::MatrixXd& patch_forces) {
  const int n = reduced.n_nodes();
  if (forces_full.rows() != 3 * n || forces_full.cols() != 6)
    throw std::invalid_argument(
        "pressure_error_estimate: forces " + std::to_string(forces_full.rows()) + "x" +
        std::to_string(forces_full.cols()) + ", expected " + std::to_string(3 * n) + "x6");
  // The normal rows of A C_r^-1 R_r = (S (x) I_3) C_r^-1 R_r: S times the patches' z rows.
  constexpr int motions[3] = {2, 3, 4}; // z translation, rotations about x and y
  Eigen::MatrixXd patch_normal(reduced.n_patches(), 3), full_normal(n, 3);
  for (int m = 0; m < 3; ++m) {
    for (int j = 0; j < reduced.n_patches(); ++j)
      patch_normal(j, m) = patch_forces(3 * j + 2, motions[m]);
    for (int k = 0; k < n; ++k)
      full_normal(k, m) = forces_full(3 * k + 2, motions[m]);
  }
  const Eigen::MatrixXd difference = reduced.shares() * patch_normal - full_normal;
  const Eigen::Matrix3d g = full_normal.transpose() * full_normal;
  const Eigen::Matrix3d h = difference.transpose() * difference;
  const Eigen::GeneralizedSelfAdjointEigenSolver<Eigen::Matrix3d> eigen(h, g,
                                                                        Eigen::EigenvaluesOnly);
  return std::sqrt(std::max(0.0, eigen.eigenvalues().maxCoeff()));
}

} // namespace

double reduction_error_estimate(const Eigen::Matrix<double, 6, 6>& k_full,
                                const ReducedSole& reduced, const Eigen::Vector3d& origin) {
  return stiffness_estimate(k_full, reduced, reduced_rigid_forces(reduced, origin), origin);
}

double pressure_error_estimate(const Eigen::MatrixXd& forces_full, const ReducedSole& reduced,
                               const Eigen::Vector3d& origin) {
  return pressure_estimate(forces_full, reduced, reduced_rigid_forces(reduced, origin));
}

namespace {

/// The loop of choose_reduction: @p reduce builds the reduced sole of a patch assignment;
/// @p k_full and @p forces_full the full sole's rigid-motion stiffness and forces.
template <class Reduce>
ReductionChoice choose_grid(const Eigen::MatrixX3d& positions,
                            const Eigen::Matrix<double, 6, 6>& k_full,
                            const Eigen::MatrixXd& forces_full, double tolerance,
                            GridSpacing spacing, PatchBasis basis, const Eigen::VectorXd& weights,
                            ReductionQuantity quantity, const Reduce& reduce) {
  if (!(tolerance > 0))
    throw std::invalid_argument("choose_reduction: tolerance " + std::to_string(tolerance) +
                                ", allowed > 0");
  const int n = static_cast<int>(positions.rows());
  const Eigen::Vector3d origin = positions.colwise().mean().transpose();
  // The grid g's choice if it meets the tolerance (reached = false otherwise or when it has as
  // many patches as nodes).
  const auto evaluate = [&](int g) -> ReductionChoice {
    const ReducedSole::ShareMatrix shares =
        ReducedSole::grid_shares(positions, g, g, spacing, basis, weights);
    if (shares.cols() >= n)
      return {g, static_cast<int>(shares.cols()), 0.0, 0.0, false};
    const ReducedSole reduced = reduce(shares);
    const Eigen::MatrixXd patch_forces = reduced_rigid_forces(reduced, origin);
    ReductionChoice c{g, reduced.n_patches(),
                      stiffness_estimate(k_full, reduced, patch_forces, origin),
                      pressure_estimate(forces_full, reduced, patch_forces), false};
    c.reached = c.estimate_of(quantity) <= tolerance;
    return c;
  };
  // A grid is done when it meets the tolerance or has as many patches as nodes (no reduction
  // left); both hold from some g on when the estimate falls with g. The nested grids g = 1, 2,
  // 4, ... bracket the first done grid (the last that is not, the first that is), bisection
  // finds it, and it is the choice if it meets the tolerance with fewer patches than nodes.
  // Whatever the estimate does, a grid is only chosen when its own estimate meets the tolerance.
  const auto is_done = [n](const ReductionChoice& c) { return c.reached || c.n_patches >= n; };
  int missed = 0, done = 1;
  ReductionChoice at_done = evaluate(done);
  while (!is_done(at_done)) {
    missed = done;
    done *= 2;
    at_done = evaluate(done);
  }
  while (done - missed > 1) {
    const int g = (missed + done) / 2;
    const ReductionChoice c = evaluate(g);
    if (is_done(c)) {
      done = g;
      at_done = c;
    } else {
      missed = g;
    }
  }
  return at_done.reached ? at_done : ReductionChoice{0, n, 0.0, 0.0, false};
}

} // namespace

ReductionChoice choose_reduction(const Eigen::MatrixX3d& positions,
                                 const Eigen::MatrixXd& compliance, double tolerance,
                                 GridSpacing spacing, const Eigen::VectorXd& weights,
                                 PatchBasis basis, ReductionQuantity quantity) {
  const Eigen::Vector3d origin = positions.colwise().mean().transpose();
  const Eigen::MatrixXd forces = rigid_motion_forces(positions, compliance, origin);
  return choose_grid(positions, stiffness_of_forces(positions, forces, origin), forces, tolerance,
                     spacing, basis, weights, quantity,
                     [&](const ReducedSole::ShareMatrix& shares) {
                       return ReducedSole(positions, compliance, shares);
                     });
}

ReductionChoice choose_reduction(const CondensedSole& sole, double tolerance, GridSpacing spacing,
                                 const Eigen::VectorXd& weights, PatchBasis basis,
                                 ReductionQuantity quantity) {
  return choose_grid(
      sole.contact_positions(), sole.rigid_motion_stiffness(), sole.rigid_motion_forces(),
      tolerance, spacing, basis, weights, quantity,
      [&](const ReducedSole::ShareMatrix& shares) { return ReducedSole(sole, shares); });
}

} // namespace plantar::coupling
