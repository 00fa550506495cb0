#pragma once
// C += alpha A B over 64 x 64 x 64 tiles, so that every Eigen kernel call keeps its blocking
// scratch on the stack (no heap allocation for any size; as in dense_lu.cc).

#include <Eigen/Core>
#include <algorithm>

namespace plantar::contact {

/// @p c (r x s) += @p alpha @p a (r x k) @p b (k x s); any dense expressions Eigen can block.
template <typename C, typename A, typename B>
void add_product_tiled(C&& c, const A& a, const B& b, double alpha) {
  constexpr Eigen::Index kTile = 64;
  const Eigen::Index rows = c.rows(), cols = c.cols(), inner = a.cols();
  for (Eigen::Index j = 0; j < cols; j += kTile) {
    const Eigen::Index jb = std::min(kTile, cols - j);
    for (Eigen::Index i = 0; i < rows; i += kTile) {
      const Eigen::Index ib = std::min(kTile, rows - i);
      for (Eigen::Index l = 0; l < inner; l += kTile) {
        const Eigen::Index lb = std::min(kTile, inner - l);
        c.block(i, j, ib, jb).noalias() += alpha * (a.block(i, l, ib, lb) * b.block(l, j, lb, jb));
      }
    }
  }
}

} // namespace plantar::contact
