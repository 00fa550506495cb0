#pragma once
// A compliance block compressed as a hierarchical matrix (H-matrix; Hackbusch, "Hierarchical
// Matrices", 2015; Bebendorf 2008): the 3n x 3n compliance C of n contact nodes (3 x 3 node
// blocks, m/N) is partitioned by a cluster tree of the nodes' positions into
//   near-field blocks C(s, t), kept dense, and
//   far-field blocks with  max(diam s, diam t) <= eta dist(s, t),  kept as U V^T of rank k,
// truncated where the discarded singular values fall below tolerance x max_i C_ii (absolute,
// per block; tests measure the resulting ||C_H - C|| / ||C||), and kept dense where the factors
// would hold more numbers than the block (so storage never exceeds the dense C). The response
// of a bonded layer decays with distance, so far blocks have low rank and the storage grows
// more slowly than n^2 (measured in docs/performance.md).
//
// Built from column slabs (one leaf cluster's 3 |leaf| columns at a time, e.g. from a sparse
// factorisation's block solves), so the dense C is never formed: the far blocks are
// recompressed as their columns arrive (QR of both factors, SVD of the small core).
//
// Products for Gauss-Seidel without passing over C (ProductState): the near-field part of
// w = C x is kept exact under single-node changes of x, the far-field part as the k
// coefficients V^T x_t of every far block; node i's w_i then costs its near update plus
// sum_blocks 3 k (O(log n) blocks), against O(n) for a dense column.

#include <Eigen/Core>
#include <algorithm>
#include <cstddef>
#include <functional>
#include <vector>

namespace plantar::contact {

struct HierarchicalSettings {
  int leaf_nodes = 16;        ///< largest cluster not split (nodes), >= 1
  double admissibility = 2.0; ///< eta > 0: far when max(diam) <= eta dist
  double tolerance = 1e-6;    ///< truncation, relative to max_i C_ii, in [0, 1)
  /// Throws std::invalid_argument naming the setting, its value and the allowed range.
  void validate() const;
};

class HierarchicalCompliance {
public:
  /// Writes the columns of C belonging to @p nodes (original node numbers) into @p columns,
  /// (3 n x 3 nodes.size(), rows in the original node order, node-major), m/N.
  using ColumnProvider =
      std::function<void(const std::vector<int>& nodes, Eigen::MatrixXd& columns)>;

  HierarchicalCompliance() = default;
  /// Clusters @p positions (n x 3 or n x 2, m) and compresses C slab by slab from
  /// @p provider. C must be symmetric (only its columns are read).
  HierarchicalCompliance(const Eigen::MatrixXd& positions, const ColumnProvider& provider,
                         const HierarchicalSettings& settings);
  /// From a dense C (3 n x 3 n), for tests and small blocks.
  static HierarchicalCompliance from_dense(const Eigen::MatrixXd& positions,
                                           const Eigen::MatrixXd& compliance,
                                           const HierarchicalSettings& settings);

  int n_nodes() const { return static_cast<int>(permutation_.size()); }
  /// y = scale C x, @p x and @p y (3 n, original node order). Does not allocate.
  void multiply(const Eigen::Ref<const Eigen::VectorXd>& x, Eigen::Ref<Eigen::VectorXd> y,
                double scale = 1.0) const {
    multiply_nodes([&](int node) -> Eigen::Vector3d { return x.segment<3>(3 * node); }, y, scale);
  }
  /// The same with x given per node: @p x_of(j) returns x_j (3) of node j (original number),
  /// e.g. rotated on the fly. Does not allocate.
  template <class NodeInput>
  void multiply_nodes(NodeInput&& x_of, Eigen::Ref<Eigen::VectorXd> y, double scale = 1.0) const;
  /// C_ii (3 x 3) of node @p node, exact (near field).
  Eigen::Matrix3d diagonal_block(int node) const;
  /// The compressed C as a dense matrix (tests).
  Eigen::MatrixXd to_dense() const;

  /// w = C x kept across single-node changes of x (see the header's comment). Sized by
  /// resize_state(); then no operation allocates.
  struct ProductState {
    Eigen::VectorXd near;         ///< 3 n, permuted order: the near-field part of C x
    Eigen::VectorXd coefficients; ///< sum_b k_b: V_b^T x_t of every far block b
  };
  void resize_state(ProductState& state) const;
  /// state <- C x, x_j = @p x_of(j) as in multiply_nodes().
  template <class NodeInput> void start_product(NodeInput&& x_of, ProductState& state) const;
  /// x_node += @p change (3): the state follows. O(near rows + 3 k log n).
  void add_change(int node, const Eigen::Vector3d& change, ProductState& state) const;
  /// (C x)_node (3) of the state's x.
  Eigen::Vector3d node_product(int node, const ProductState& state) const;
  /// out = scale C x (3 n, original order) of the state's x.
  void write_product(const ProductState& state, Eigen::Ref<Eigen::VectorXd> out,
                     double scale = 1.0) const;

  /// Doubles stored in the blocks, as bytes; and the dense C's bytes 8 (3 n)^2.
  std::size_t bytes() const;
  std::size_t dense_bytes() const;
  int n_dense_blocks() const;
  int n_low_rank_blocks() const;
  int max_rank() const;

private:
  struct Cluster {
    int begin = 0, end = 0;    // permuted node range
    Eigen::Vector3d low, high; // bounding box
    int first_child = -1;      // children first_child, first_child + 1; -1: leaf
    int size() const { return end - begin; }
  };
  struct Block {
    int row = 0, col = 0; // clusters
    bool low_rank = false;
    Eigen::MatrixXd dense;      // 3|row| x 3|col|, or
    Eigen::MatrixXd u, v;       // 3|row| x k, 3|col| x k
    int coefficient_offset = 0; // into ProductState::coefficients
  };
  void build_clusters(const Eigen::MatrixXd& positions, int leaf_nodes);
  void build_blocks(int row, int col, double eta);
  void compress(const ColumnProvider& provider, double tolerance);

  std::vector<int> permutation_; // permuted position -> node
  std::vector<int> inverse_;     // node -> permuted position
  std::vector<int> leaf_of_;     // permuted position -> leaf cluster index
  std::vector<Cluster> clusters_;
  std::vector<Block> blocks_;
  // Per leaf cluster: the blocks whose column cluster contains it, and the far blocks whose
  // row cluster contains it.
  std::vector<std::vector<int>> column_blocks_;
  std::vector<std::vector<int>> row_far_blocks_;
  std::vector<int> diagonal_block_of_leaf_; // the dense (leaf, leaf) block
  int n_coefficients_ = 0;
};

template <class NodeInput>
void HierarchicalCompliance::multiply_nodes(NodeInput&& x_of, Eigen::Ref<Eigen::VectorXd> y,
                                            double scale) const {
  y.setZero();
  constexpr Eigen::Index kChunk = 32; // the k-vector V^T x_t on the stack, by chunks
  double stack[kChunk];
  for (const Block& b : blocks_) {
    const Cluster& s = clusters_[b.row];
    const Cluster& t = clusters_[b.col];
    if (b.low_rank) {
      for (Eigen::Index start = 0; start < b.u.cols(); start += kChunk) {
        const Eigen::Index width = std::min(kChunk, b.u.cols() - start);
        Eigen::Map<Eigen::VectorXd> part(stack, width);
        part.setZero();
        for (int j = 0; j < t.size(); ++j)
          part.noalias() +=
              b.v.block(3 * j, start, 3, width).transpose() * x_of(permutation_[t.begin + j]);
        for (int i = 0; i < s.size(); ++i)
          y.template segment<3>(3 * permutation_[s.begin + i]).noalias() +=
              scale * (b.u.block(3 * i, start, 3, width) * part);
      }
    } else {
      for (int j = 0; j < t.size(); ++j) {
        const Eigen::Vector3d x_j = scale * x_of(permutation_[t.begin + j]);
        for (int i = 0; i < s.size(); ++i)
          y.template segment<3>(3 * permutation_[s.begin + i]).noalias() +=
              b.dense.template block<3, 3>(3 * i, 3 * j) * x_j;
      }
    }
  }
}

template <class NodeInput>
void HierarchicalCompliance::start_product(NodeInput&& x_of, ProductState& state) const {
  state.near.setZero();
  for (const Block& b : blocks_) {
    const Cluster& s = clusters_[b.row];
    const Cluster& t = clusters_[b.col];
    if (b.low_rank) {
      auto c = state.coefficients.segment(b.coefficient_offset, b.u.cols());
      c.setZero();
      for (int j = 0; j < t.size(); ++j)
        c.noalias() +=
            b.v.template middleRows<3>(3 * j).transpose() * x_of(permutation_[t.begin + j]);
    } else {
      for (int j = 0; j < t.size(); ++j)
        state.near.segment(3 * s.begin, 3 * s.size()).noalias() +=
            b.dense.template middleCols<3>(3 * j) * x_of(permutation_[t.begin + j]);
    }
  }
}

} // namespace plantar::contact
