#include "contact/semidefinite_cholesky.h"

#include <cmath>

namespace plantar::contact {

int semidefinite_cholesky(Eigen::Ref<Eigen::MatrixXd> a, double relative_pivot) {
  const int n = static_cast<int>(a.rows());
  if (n == 0)
    return 0;
  const double largest = a.diagonal().maxCoeff();
  int rank = 0;
  for (int j = 0; j < n; ++j) {
    double d = a(j, j) - a.row(j).head(j).squaredNorm();
    if (!(d > relative_pivot * largest)) {
      a.col(j).tail(n - j).setZero();
      continue;
    }
    d = std::sqrt(d);
    a(j, j) = d;
    for (int i = j + 1; i < n; ++i) {
      a(i, j) = (a(i, j) - a.row(i).head(j).dot(a.row(j).head(j))) / d;
    }
    ++rank;
  }
  return rank;
}

} // namespace plantar::contact
