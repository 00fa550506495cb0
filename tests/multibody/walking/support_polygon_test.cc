// walking::hull_margin, a point's signed distance to the boundary of a convex hull, against
// closed forms (two soles' rectangles: the distance to the nearest side; a point outside), a
// dense computation (the edges of walking::convex_hull at random point sets) and degenerate
// sets (collinear points, repeated points).
#include "multibody/walking/support_polygon.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <limits>
#include <random>

namespace plantar::walking {
namespace {

/// The 8 corners of two soles (half sizes hx, hy) centred at (0, +-y0), and the midpoints of
/// their sides (collinear points on the hull's edges).
Eigen::Matrix2Xd two_soles(double hx, double hy, double y0) {
  Eigen::Matrix2Xd points(2, 12);
  int k = 0;
  for (const double yc : {-y0, y0}) {
    for (const double sx : {-1.0, 1.0})
      for (const double sy : {-1.0, 1.0})
        points.col(k++) << sx * hx, yc + sy * hy;
    points.col(k++) << 0.0, yc - hy;
    points.col(k++) << hx, yc;
  }
  return points;
}

TEST(HullMargin, TwoSolesAgainstTheNearestSide) {
  const double hx = 0.1086, hy = 0.069, y0 = 0.105;
  const Eigen::Matrix2Xd points = two_soles(hx, hy, y0);
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> x(-0.15, 0.15), y(-0.2, 0.2);
  double worst = 0;
  for (int trial = 0; trial < 200; ++trial) {
    const Eigen::Vector2d p(x(rng), y(rng));
    // The hull is the rectangle |x| <= hx, |y| <= y0 + hy.
    const double inside = std::min(hx - std::abs(p.x()), y0 + hy - std::abs(p.y()));
    const double m = hull_margin(p, points);
    if (inside >= 0) {
      worst = std::max(worst, std::abs(m - inside));
    } else {
      // Outside: negative, minus the largest excess over one side's line.
      EXPECT_LT(m, 0.0);
      const double excess = std::max(std::abs(p.x()) - hx, std::abs(p.y()) - y0 - hy);
      EXPECT_NEAR(m, -excess, 1e-14);
    }
  }
  std::printf("two soles: margin against the nearest side, worst error %.2e m\n", worst);
  EXPECT_LT(worst, 1e-14);
  // One sole (the right one's 4 corners): its centre is hy from the long sides.
  EXPECT_NEAR(hull_margin(Eigen::Vector2d(0, -y0), points.leftCols(4)), std::min(hx, hy), 1e-15);
}

TEST(HullMargin, RandomSetsAgainstTheHullsEdges) {
  std::mt19937 rng(11);
  std::normal_distribution<double> normal(0.0, 0.1);
  double worst = 0;
  for (int trial = 0; trial < 100; ++trial) {
    const int n = 3 + trial % 12;
    Eigen::Matrix2Xd points(2, n);
    for (int k = 0; k < n; ++k)
      points.col(k) << normal(rng), normal(rng);
    const Eigen::Matrix2Xd hull = convex_hull(points);
    const Eigen::Vector2d p(normal(rng), normal(rng));
    double expected = std::numeric_limits<double>::infinity();
    for (int i = 0; i < hull.cols(); ++i) {
      const Eigen::Vector2d a = hull.col(i), b = hull.col((i + 1) % hull.cols());
      const Eigen::Vector2d inward = Eigen::Vector2d(-(b - a).y(), (b - a).x()).normalized();
      expected = std::min(expected, inward.dot(p - a));
    }
    worst = std::max(worst, std::abs(hull_margin(p, points) - expected));
  }
  std::printf("random sets (3-14 points): against convex_hull's edges, worst %.2e m\n", worst);
  EXPECT_LT(worst, 1e-14);
}

TEST(HullMargin, DegenerateSets) {
  Eigen::Matrix2Xd line(2, 3);
  line << 0, 1, 2, 0, 1, 2;
  EXPECT_LE(hull_margin(Eigen::Vector2d(1, 1), line), 0.0);
  EXPECT_NEAR(hull_margin(Eigen::Vector2d(1, 1), line), 0.0, 1e-15); // on the line
  EXPECT_NEAR(hull_margin(Eigen::Vector2d(0, 1), line), -std::sqrt(0.5), 1e-15);
  Eigen::Matrix2Xd repeated(2, 5); // a unit square with a repeated corner
  repeated << 0, 1, 1, 0, 1, 0, 0, 1, 1, 1;
  EXPECT_NEAR(hull_margin(Eigen::Vector2d(0.5, 0.25), repeated), 0.25, 1e-15);
  EXPECT_EQ(hull_margin(Eigen::Vector2d(0, 0), Eigen::Matrix2Xd(2, 1).setZero()),
            -std::numeric_limits<double>::infinity());
}

} // namespace
} // namespace plantar::walking
