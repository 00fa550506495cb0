#include "contact/hierarchical_compliance.h"

#include <Eigen/QR>
#include <Eigen/SVD>
#include <algorithm>
#include <cmath>
#include <numeric>
#include <sstream>
#include <stdexcept>

namespace plantar::contact {

void HierarchicalSettings::validate() const {
  auto fail = [](const char* name, double value, const char* range) {
    std::ostringstream out;
    out << "hierarchical compliance: " << name << " = " << value << " is out of range (" << range
        << ")";
    throw std::invalid_argument(out.str());
  };
  if (leaf_nodes < 1)
    fail("leaf nodes", leaf_nodes, ">= 1");
  if (!(admissibility > 0.0) || !std::isfinite(admissibility))
    fail("admissibility", admissibility, "finite, > 0");
  if (!(tolerance >= 0.0 && tolerance < 1.0))
    fail("tolerance", tolerance, "[0, 1)");
}

namespace {

double box_distance(const Eigen::Vector3d& low_a, const Eigen::Vector3d& high_a,
                    const Eigen::Vector3d& low_b, const Eigen::Vector3d& high_b) {
  const Eigen::Vector3d gap =
      (low_b - high_a).cwiseMax(low_a - high_b).cwiseMax(Eigen::Vector3d::Zero());
  return gap.norm();
}

// The rank-k truncation of U V^T, U (r x c), V (s x c): thin QR of both, SVD of the c x c
// core, singular values kept while the discarded tail's 2-norm exceeds @p threshold.
void recompress(Eigen::MatrixXd& u, Eigen::MatrixXd& v, double threshold) {
  const Eigen::Index c = u.cols();
  if (c == 0)
    return;
  Eigen::HouseholderQR<Eigen::MatrixXd> qr_u(u), qr_v(v);
  const Eigen::Index cu = std::min(u.rows(), c), cv = std::min(v.rows(), c);
  const Eigen::MatrixXd r_u = qr_u.matrixQR().topRows(cu).triangularView<Eigen::Upper>();
  const Eigen::MatrixXd r_v = qr_v.matrixQR().topRows(cv).triangularView<Eigen::Upper>();
  const Eigen::MatrixXd core = r_u * r_v.transpose(); // cu x cv
  Eigen::JacobiSVD<Eigen::MatrixXd> svd(core, Eigen::ComputeThinU | Eigen::ComputeThinV);
  const Eigen::VectorXd& s = svd.singularValues();
  Eigen::Index k = s.size();
  double tail = 0.0;
  while (k > 0 && std::sqrt(tail + s[k - 1] * s[k - 1]) <= threshold) {
    tail += s[k - 1] * s[k - 1];
    --k;
  }
  const Eigen::MatrixXd q_u = qr_u.householderQ() * Eigen::MatrixXd::Identity(u.rows(), cu);
  const Eigen::MatrixXd q_v = qr_v.householderQ() * Eigen::MatrixXd::Identity(v.rows(), cv);
  u = q_u * (svd.matrixU().leftCols(k) * s.head(k).asDiagonal());
  v = q_v * svd.matrixV().leftCols(k);
}

} // namespace

void HierarchicalCompliance::build_clusters(const Eigen::MatrixXd& positions, int leaf_nodes) {
  const int n = static_cast<int>(positions.rows());
  Eigen::MatrixX3d points = Eigen::MatrixX3d::Zero(n, 3);
  points.leftCols(std::min<Eigen::Index>(3, positions.cols())) =
      positions.leftCols(std::min<Eigen::Index>(3, positions.cols()));
  permutation_.resize(n);
  std::iota(permutation_.begin(), permutation_.end(), 0);
  clusters_.clear();
  clusters_.reserve(2 * n);
  auto bound = [&](Cluster& c) {
    c.low = points.row(permutation_[c.begin]).transpose();
    c.high = c.low;
    for (int i = c.begin + 1; i < c.end; ++i) {
      c.low = c.low.cwiseMin(points.row(permutation_[i]).transpose());
      c.high = c.high.cwiseMax(points.row(permutation_[i]).transpose());
    }
  };
  Cluster root;
  root.begin = 0;
  root.end = n;
  bound(root);
  clusters_.push_back(root);
  // Breadth-first bisection along the box's longest axis at the median.
  for (std::size_t c = 0; c < clusters_.size(); ++c) {
    if (clusters_[c].size() <= leaf_nodes)
      continue;
    int axis;
    (clusters_[c].high - clusters_[c].low).maxCoeff(&axis);
    const int begin = clusters_[c].begin, end = clusters_[c].end, middle = (begin + end) / 2;
    std::nth_element(permutation_.begin() + begin, permutation_.begin() + middle,
                     permutation_.begin() + end,
                     [&](int a, int b) { return points(a, axis) < points(b, axis); });
    Cluster left, right;
    left.begin = begin;
    left.end = middle;
    right.begin = middle;
    right.end = end;
    bound(left);
    bound(right);
    clusters_[c].first_child = static_cast<int>(clusters_.size());
    clusters_.push_back(left);
    clusters_.push_back(right);
  }
  inverse_.resize(n);
  leaf_of_.resize(n);
  for (int i = 0; i < n; ++i)
    inverse_[permutation_[i]] = i;
  for (int c = 0; c < static_cast<int>(clusters_.size()); ++c)
    if (clusters_[c].first_child < 0)
      for (int i = clusters_[c].begin; i < clusters_[c].end; ++i)
        leaf_of_[i] = c;
}

void HierarchicalCompliance::build_blocks(int row, int col, double eta) {
  const Cluster& s = clusters_[row];
  const Cluster& t = clusters_[col];
  const double diameter = std::max((s.high - s.low).norm(), (t.high - t.low).norm());
  const double distance = box_distance(s.low, s.high, t.low, t.high);
  if (distance > 0.0 && diameter <= eta * distance) {
    Block b;
    b.row = row;
    b.col = col;
    b.low_rank = true;
    b.u.resize(3 * s.size(), 0);
    b.v.resize(3 * t.size(), 0);
    blocks_.push_back(std::move(b));
    return;
  }
  if (s.first_child < 0 || t.first_child < 0) {
    Block b;
    b.row = row;
    b.col = col;
    b.dense.setZero(3 * s.size(), 3 * t.size());
    blocks_.push_back(std::move(b));
    return;
  }
  for (int i = 0; i < 2; ++i)
    for (int j = 0; j < 2; ++j)
      build_blocks(s.first_child + i, t.first_child + j, eta);
}

void HierarchicalCompliance::compress(const ColumnProvider& provider, double tolerance) {
  const int n = n_nodes();
  const int n_clusters = static_cast<int>(clusters_.size());
  column_blocks_.assign(n_clusters, {});
  row_far_blocks_.assign(n_clusters, {});
  diagonal_block_of_leaf_.assign(n_clusters, -1);
  // A block's column (row) cluster contains the leaves below it.
  auto for_leaves = [&](int cluster, auto&& f) {
    const Cluster& c = clusters_[cluster];
    for (int i = c.begin; i < c.end;) {
      const int leaf = leaf_of_[i];
      f(leaf);
      i = clusters_[leaf].end;
    }
  };
  for (int b = 0; b < static_cast<int>(blocks_.size()); ++b) {
    for_leaves(blocks_[b].col, [&](int leaf) { column_blocks_[leaf].push_back(b); });
    if (blocks_[b].low_rank)
      for_leaves(blocks_[b].row, [&](int leaf) { row_far_blocks_[leaf].push_back(b); });
    else if (blocks_[b].row == blocks_[b].col)
      diagonal_block_of_leaf_[blocks_[b].row] = b;
  }
  double scale = 0.0; // max_i C_ii of the columns read so far
  std::vector<int> nodes;
  Eigen::MatrixXd columns, permuted;
  for (int leaf = 0; leaf < n_clusters; ++leaf) {
    const Cluster& l = clusters_[leaf];
    if (l.first_child >= 0)
      continue;
    nodes.assign(permutation_.begin() + l.begin, permutation_.begin() + l.end);
    columns.resize(3 * n, 3 * l.size());
    provider(nodes, columns);
    if (columns.rows() != 3 * n || columns.cols() != 3 * l.size() || !columns.allFinite())
      throw std::invalid_argument("hierarchical compliance: the column provider returned a " +
                                  std::to_string(columns.rows()) + " x " +
                                  std::to_string(columns.cols()) +
                                  " slab (or non-finite entries), expected " +
                                  std::to_string(3 * n) + " x " + std::to_string(3 * l.size()));
    permuted.resize(3 * n, 3 * l.size());
    for (int i = 0; i < n; ++i)
      permuted.middleRows<3>(3 * i) = columns.middleRows<3>(3 * permutation_[i]);
    for (int j = 0; j < 3 * l.size(); ++j)
      scale = std::max(scale, std::abs(permuted(3 * l.begin + j, j)));
    for (const int b : column_blocks_[leaf]) {
      Block& block = blocks_[b];
      const Cluster& s = clusters_[block.row];
      const Cluster& t = clusters_[block.col];
      const auto slab = permuted.middleRows(3 * s.begin, 3 * s.size());
      const int offset = 3 * (l.begin - t.begin);
      if (!block.low_rank) {
        block.dense.middleCols(offset, 3 * l.size()) = slab;
        continue;
      }
      // U V^T + slab E^T, E the slab's columns of the identity; then truncated.
      const Eigen::Index k = block.u.cols();
      Eigen::MatrixXd u(block.u.rows(), k + slab.cols()), v(block.v.rows(), k + slab.cols());
      u << block.u, slab;
      v.leftCols(k) = block.v;
      v.rightCols(slab.cols()).setZero();
      v.block(offset, k, slab.cols(), slab.cols()).setIdentity();
      recompress(u, v, tolerance * scale);
      block.u = std::move(u);
      block.v = std::move(v);
    }
  }
  // A far block whose factors hold more numbers than its entries is kept dense.
  for (Block& b : blocks_)
    if (b.low_rank && b.u.cols() * (b.u.rows() + b.v.rows()) >= b.u.rows() * b.v.rows()) {
      b.dense = b.u * b.v.transpose();
      b.u.resize(0, 0);
      b.v.resize(0, 0);
      b.low_rank = false;
    }
  for (int c = 0; c < n_clusters; ++c)
    row_far_blocks_[c].erase(std::remove_if(row_far_blocks_[c].begin(), row_far_blocks_[c].end(),
                                            [&](int b) { return !blocks_[b].low_rank; }),
                             row_far_blocks_[c].end());
  n_coefficients_ = 0;
  for (Block& b : blocks_)
    if (b.low_rank) {
      b.coefficient_offset = n_coefficients_;
      n_coefficients_ += static_cast<int>(b.u.cols());
    }
}

HierarchicalCompliance::HierarchicalCompliance(const Eigen::MatrixXd& positions,
                                               const ColumnProvider& provider,
                                               const HierarchicalSettings& settings) {
  settings.validate();
  if (positions.rows() < 1 || positions.cols() < 2 || positions.cols() > 3 ||
      !positions.allFinite())
    throw std::invalid_argument("hierarchical compliance: positions must be n x 2 or n x 3, "
                                "n >= 1, finite; got " +
                                std::to_string(positions.rows()) + " x " +
                                std::to_string(positions.cols()));
  build_clusters(positions, settings.leaf_nodes);
  build_blocks(0, 0, settings.admissibility);
  compress(provider, settings.tolerance);
}

HierarchicalCompliance HierarchicalCompliance::from_dense(const Eigen::MatrixXd& positions,
                                                          const Eigen::MatrixXd& compliance,
                                                          const HierarchicalSettings& settings) {
  const Eigen::Index n3 = 3 * positions.rows();
  if (compliance.rows() != n3 || compliance.cols() != n3)
    throw std::invalid_argument(
        "hierarchical compliance: the compliance is " + std::to_string(compliance.rows()) + " x " +
        std::to_string(compliance.cols()) + ", expected " + std::to_string(n3) + " square");
  return HierarchicalCompliance(
      positions,
      [&](const std::vector<int>& nodes, Eigen::MatrixXd& columns) {
        for (std::size_t j = 0; j < nodes.size(); ++j)
          columns.middleCols<3>(3 * j) = compliance.middleCols<3>(3 * nodes[j]);
      },
      settings);
}

void HierarchicalCompliance::resize_state(ProductState& state) const {
  state.near.setZero(3 * n_nodes());
  state.coefficients.setZero(n_coefficients_);
}

void HierarchicalCompliance::add_change(int node, const Eigen::Vector3d& change,
                                        ProductState& state) const {
  const int i = inverse_[node];
  for (const int index : column_blocks_[leaf_of_[i]]) {
    const Block& b = blocks_[index];
    const int local = 3 * (i - clusters_[b.col].begin);
    if (b.low_rank)
      state.coefficients.segment(b.coefficient_offset, b.u.cols()).noalias() +=
          b.v.middleRows<3>(local).transpose() * change;
    else
      state.near.segment(3 * clusters_[b.row].begin, b.dense.rows()).noalias() +=
          b.dense.middleCols<3>(local) * change;
  }
}

Eigen::Vector3d HierarchicalCompliance::node_product(int node, const ProductState& state) const {
  const int i = inverse_[node];
  Eigen::Vector3d w = state.near.segment<3>(3 * i);
  for (const int index : row_far_blocks_[leaf_of_[i]]) {
    const Block& b = blocks_[index];
    w.noalias() += b.u.middleRows<3>(3 * (i - clusters_[b.row].begin)) *
                   state.coefficients.segment(b.coefficient_offset, b.u.cols());
  }
  return w;
}

void HierarchicalCompliance::write_product(const ProductState& state,
                                           Eigen::Ref<Eigen::VectorXd> out, double scale) const {
  const int n = n_nodes();
  for (int i = 0; i < n; ++i)
    out.segment<3>(3 * permutation_[i]) = scale * state.near.segment<3>(3 * i);
  for (const Block& b : blocks_) {
    if (!b.low_rank)
      continue;
    const Cluster& s = clusters_[b.row];
    const auto c = state.coefficients.segment(b.coefficient_offset, b.u.cols());
    for (int i = 0; i < s.size(); ++i)
      out.segment<3>(3 * permutation_[s.begin + i]).noalias() +=
          scale * (b.u.middleRows<3>(3 * i) * c);
  }
}

Eigen::Matrix3d HierarchicalCompliance::diagonal_block(int node) const {
  const int i = inverse_[node];
  const int leaf = leaf_of_[i];
  const int local = 3 * (i - clusters_[leaf].begin);
  return blocks_[diagonal_block_of_leaf_[leaf]].dense.block<3, 3>(local, local);
}

Eigen::MatrixXd HierarchicalCompliance::to_dense() const {
  const int n = n_nodes();
  Eigen::MatrixXd permuted = Eigen::MatrixXd::Zero(3 * n, 3 * n), out(3 * n, 3 * n);
  for (const Block& b : blocks_) {
    const Cluster& s = clusters_[b.row];
    const Cluster& t = clusters_[b.col];
    permuted.block(3 * s.begin, 3 * t.begin, 3 * s.size(), 3 * t.size()) =
        b.low_rank ? Eigen::MatrixXd(b.u * b.v.transpose()) : b.dense;
  }
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j)
      out.block<3, 3>(3 * permutation_[i], 3 * permutation_[j]) =
          permuted.block<3, 3>(3 * i, 3 * j);
  return out;
}

std::size_t HierarchicalCompliance::bytes() const {
  std::size_t doubles = 0;
  for (const Block& b : blocks_)
    doubles += static_cast<std::size_t>(b.dense.size() + b.u.size() + b.v.size());
  return 8 * doubles;
}

std::size_t HierarchicalCompliance::dense_bytes() const {
  const std::size_t n3 = 3 * static_cast<std::size_t>(n_nodes());
  return 8 * n3 * n3;
}

int HierarchicalCompliance::n_dense_blocks() const {
  return static_cast<int>(
      std::count_if(blocks_.begin(), blocks_.end(), [](const Block& b) { return !b.low_rank; }));
}

int HierarchicalCompliance::n_low_rank_blocks() const {
  return static_cast<int>(blocks_.size()) - n_dense_blocks();
}

int HierarchicalCompliance::max_rank() const {
  int k = 0;
  for (const Block& b : blocks_)
    k = std::max(k, static_cast<int>(b.u.cols()));
  return k;
}

} // namespace plantar::contact
