#include "multibody/walking/support_polygon.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>
#include <stdexcept>
#include <string>
#include <vector>

namespace plantar::walking {

namespace {

double cross(const Eigen::Vector2d& o, const Eigen::Vector2d& a, const Eigen::Vector2d& b) {
  return (a - o).x() * (b - o).y() - (a - o).y() * (b - o).x();
}

} // namespace

Eigen::Matrix2Xd convex_hull(const Eigen::Matrix2Xd& points) {
  const int n = static_cast<int>(points.cols());
  if (n < 1)
    throw std::invalid_argument("convex_hull: no points");
  std::vector<int> order(n);
  std::iota(order.begin(), order.end(), 0);
  std::sort(order.begin(), order.end(), [&points](int a, int b) {
    return points(0, a) < points(0, b) ||
           (points(0, a) == points(0, b) && points(1, a) < points(1, b));
  });
  // Lower then upper chain; a turn that is not strictly counter-clockwise is dropped.
  std::vector<int> hull(2 * n);
  int k = 0;
  for (int i = 0; i < n; ++i) {
    while (k >= 2 &&
           cross(points.col(hull[k - 2]), points.col(hull[k - 1]), points.col(order[i])) <= 0)
      --k;
    hull[k++] = order[i];
  }
  for (int i = n - 2, lower = k + 1; i >= 0; --i) {
    while (k >= lower &&
           cross(points.col(hull[k - 2]), points.col(hull[k - 1]), points.col(order[i])) <= 0)
      --k;
    hull[k++] = order[i];
  }
  const int m = n == 1 ? 1 : k - 1; // the last point repeats the first
  Eigen::Matrix2Xd out(2, m);
  for (int i = 0; i < m; ++i)
    out.col(i) = points.col(hull[i]);
  return out;
}

namespace {

/// The point at depth >= d in @p polygon nearest to p (nearest_in_polygon); false if none.
bool nearest_at_depth(const Eigen::Vector2d& p, const Eigen::Matrix2Xd& polygon, double d,
                      Eigen::Vector2d& out) {
  const int m = static_cast<int>(polygon.cols());
  const double tolerance = 1e-12 * std::max(1.0, polygon.cwiseAbs().maxCoeff());
  // Edge i: n_i . x >= c_i.
  auto normal = [&polygon, m](int i) {
    const Eigen::Vector2d e = polygon.col((i + 1) % m) - polygon.col(i);
    return Eigen::Vector2d(-e.y(), e.x()).normalized();
  };
  auto offset = [&](int i) { return normal(i).dot(polygon.col(i)) + d; };
  auto inside = [&](const Eigen::Vector2d& x) {
    for (int i = 0; i < m; ++i)
      if (normal(i).dot(x) < offset(i) - tolerance)
        return false;
    return true;
  };
  if (inside(p)) {
    out = p;
    return true;
  }
  double best_distance = std::numeric_limits<double>::infinity();
  auto consider = [&](const Eigen::Vector2d& x) {
    const double distance = (x - p).squaredNorm();
    if (distance < best_distance && inside(x)) {
      out = x;
      best_distance = distance;
    }
  };
  for (int i = 0; i < m; ++i) {
    const Eigen::Vector2d ni = normal(i);
    const double ci = offset(i);
    consider(p + (ci - ni.dot(p)) * ni);
    for (int j = i + 1; j < m; ++j) {
      const Eigen::Vector2d nj = normal(j);
      const double det = ni.x() * nj.y() - ni.y() * nj.x();
      if (std::abs(det) < 1e-12)
        continue;
      const double cj = offset(j);
      consider(
          Eigen::Vector2d((ci * nj.y() - cj * ni.y()) / det, (ni.x() * cj - nj.x() * ci) / det));
    }
  }
  return std::isfinite(best_distance);
}

} // namespace

Eigen::Vector2d nearest_in_polygon(const Eigen::Vector2d& p, const Eigen::Matrix2Xd& polygon,
                                   double margin) {
  Eigen::Vector2d x = p;
  if (nearest_at_depth(p, polygon, margin, x))
    return x;
  if (polygon.cols() < 3 || !nearest_at_depth(p, polygon, 0.0, x))
    return p; // a degenerate polygon: nothing to clamp to
  return x;
}

double hull_margin(const Eigen::Vector2d& p, const Eigen::Ref<const Eigen::Matrix2Xd>& points) {
  const int n = static_cast<int>(points.cols());
  double margin = -std::numeric_limits<double>::infinity();
  bool found = false;
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j) {
      const Eigen::Vector2d a = points.col(i), b = points.col(j);
      const double length = (b - a).norm();
      if (!(length > 0))
        continue;
      bool edge = true;
      for (int k = 0; k < n && edge; ++k)
        edge = cross(a, b, points.col(k)) >= -1e-12 * length;
      if (!edge)
        continue;
      const double d = cross(a, b, p) / length;
      margin = found ? std::min(margin, d) : d;
      found = true;
    }
  return margin;
}

} // namespace plantar::walking
