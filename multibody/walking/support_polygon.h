// The support polygon of a sole: the convex hull of its points on the ground, the point of it,
// shrunk by a margin, nearest to a target (where a ZMP or CoP target can be held), and a
// point's margin to the hull's boundary (how far a ZMP is from tipping).
#pragma once

#include <Eigen/Core>

namespace plantar::walking {

/// The convex hull of @p points (2 x n, n >= 1) [m], counter-clockwise, without collinear
/// points (Andrew's monotone chain, O(n log n)): 2 x m, m <= n.
Eigen::Matrix2Xd convex_hull(const Eigen::Matrix2Xd& points);

/// The point of the convex polygon @p polygon (2 x m, counter-clockwise, m >= 3) shrunk by
/// @p margin [m] nearest to @p p: argmin |x - p| subject to n_i . (x - v_i) >= margin for
/// every edge i (v_i -> v_i+1, n_i its inward unit normal). p itself when it satisfies them;
/// otherwise the best of the projections on one offset edge line and the intersections of two
/// that satisfy every constraint (O(m^3), exact). When the margin leaves nothing of the
/// polygon (a triangle of inscribed radius < margin), the same with margin 0; p itself for a
/// degenerate polygon. No heap allocation.
Eigen::Vector2d nearest_in_polygon(const Eigen::Vector2d& p, const Eigen::Matrix2Xd& polygon,
                                   double margin);

/// The signed distance [m] from @p p to the boundary of the convex hull of @p points (2 x n):
/// min over the hull's edges (a, b) of n . (p - a), n the edge's inward unit normal; positive
/// inside, negative outside (there a lower bound of minus the distance). The edges are the
/// ordered pairs with every point on or left of a -> b (1e-12 m), so the hull is not built:
/// O(n^3), no heap allocation. Collinear points (no area) give a value <= 0; n < 2: -inf.
double hull_margin(const Eigen::Vector2d& p, const Eigen::Ref<const Eigen::Matrix2Xd>& points);

} // namespace plantar::walking
