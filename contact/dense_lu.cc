#include "contact/dense_lu.h"

#include <algorithm>
#include <cmath>

namespace plantar::contact {

bool lu_in_place(Eigen::Ref<Eigen::MatrixXd> a, Eigen::Ref<Eigen::VectorXi> pivots) {
  constexpr Eigen::Index kTile = 64;
  const Eigen::Index n = a.rows();
  for (Eigen::Index k = 0; k < n; k += kTile) {
    const Eigen::Index kb = std::min(kTile, n - k);
    // Panel: columns k .. k + kb, rows k .. n.
    for (Eigen::Index j = k; j < k + kb; ++j) {
      Eigen::Index pivot = j;
      double largest = std::abs(a(j, j));
      for (Eigen::Index i = j + 1; i < n; ++i)
        if (std::abs(a(i, j)) > largest) {
          largest = std::abs(a(i, j));
          pivot = i;
        }
      pivots[j] = static_cast<int>(pivot);
      if (largest == 0.0)
        return false;
      if (pivot != j)
        a.row(j).swap(a.row(pivot));
      const double inverse = 1.0 / a(j, j);
      for (Eigen::Index i = j + 1; i < n; ++i)
        a(i, j) *= inverse;
      for (Eigen::Index c = j + 1; c < k + kb; ++c) { // rank-1 update inside the panel
        const double u = a(j, c);
        if (u != 0.0)
          for (Eigen::Index i = j + 1; i < n; ++i)
            a(i, c) -= a(i, j) * u;
      }
    }
    if (k + kb >= n)
      break;
    const auto l11 = a.block(k, k, kb, kb);
    for (Eigen::Index j = k + kb; j < n; j += kTile) { // U12 = L11^-1 A12
      auto a12 = a.block(k, j, kb, std::min(kTile, n - j));
      l11.triangularView<Eigen::UnitLower>().solveInPlace(a12);
    }
    for (Eigen::Index j = k + kb; j < n; j += kTile) { // A22 -= L21 U12
      const Eigen::Index jb = std::min(kTile, n - j);
      for (Eigen::Index i = k + kb; i < n; i += kTile) {
        const Eigen::Index ib = std::min(kTile, n - i);
        a.block(i, j, ib, jb).noalias() -= a.block(i, k, ib, kb) * a.block(k, j, kb, jb);
      }
    }
  }
  return true;
}

void lu_solve_in_place(const Eigen::Ref<const Eigen::MatrixXd>& lu,
                       const Eigen::Ref<const Eigen::VectorXi>& pivots,
                       Eigen::Ref<Eigen::VectorXd> x) {
  const Eigen::Index n = lu.rows();
  for (Eigen::Index i = 0; i < n; ++i)
    if (pivots[i] != i)
      std::swap(x[i], x[pivots[i]]);
  lu.triangularView<Eigen::UnitLower>().solveInPlace(x);
  lu.triangularView<Eigen::Upper>().solveInPlace(x);
}

} // namespace plantar::contact
