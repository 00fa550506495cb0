// Footstep placement on a terrain: each sole rests on the plane through three of its points
// that carries its centre, with no point below the ground (a walk planned for the ground it
// walks on).
#pragma once

#include "contact/terrain.h"
#include "multibody/walking/footstep_plan.h"

#include <Eigen/Core>

namespace plantar::walking {

/// The points of a sole that may touch the ground, (x, y) in the sole frame [m] (2 x n, n >= 3,
/// the sole centre (0, 0) inside their convex hull): e.g. a rigid foot's contact points, or a
/// grid over the sole's outline (sole_grid).
using SolePoints = Eigen::Matrix2Xd;

/// An m x m grid over the length x width rectangle centred on the sole frame (m >= 2).
SolePoints sole_grid(double length, double width, int m);

/// Places @p step (x, y, yaw kept) on @p terrain, as a rigid sole at rest: with h_i the ground
/// heights under the points p_i (yawed by step.yaw about (x, y)), the plane
///   z = a + b x' + c y'   (x', y' the yawed sole axes, origin at (x, y))
/// is the lowest one at the centre with h_i <= a + b x'_i + c y'_i for every point (of planes as
/// low there, e.g. through a point at the centre on a peak, the least tilted): the facet of
/// the points' upper convex hull above the centre, through three points whose triangle holds
/// the centre (brute force over the triples, O(n^4)). The tilt is R_y(pitch) R_x(roll) e_z =
/// n = (-b, -c, 1) / |.| in the yawed frame: pitch = -atan(b), roll = asin(c / |(-b, -c, 1)|).
/// Tilted, the points move horizontally by O(tilt^2): the facet is searched again at their
/// tilted positions until the tilt is fixed (to 1e-14 rad, at most 20 passes); last, the plane
/// moves by max_i (h(p_i) - p_z,i) so that no point is below the ground and the lowest is on it.
/// The support (Footstep::support) is the convex hull of the facet's three points and of any
/// other within 1e-9 m of the ground (all of them on a plane; on a rough ground the three, whose
/// triangle may hold the centre on an edge: a rectangle rests on three corners), and
/// the ZMP target (zmp_x, zmp_y) the point of it shrunk by @p zmp_margin [m] nearest to the
/// centre (nearest_in_polygon): the centre itself when it is that far inside, or when the
/// support is too thin for the margin (then the foot rocks onto a fourth point at a small tilt,
/// the gap over the sole's size, rather than holding the ZMP near a far corner).
/// @throws std::invalid_argument for fewer than 3 points or a centre outside their hull.
Footstep place_on_terrain(const contact::Terrain& terrain, const Footstep& step,
                          const SolePoints& points, double zmp_margin);

/// Signed distance (m) from the sole centre (0, 0) to the boundary of @p support (a convex
/// polygon, counter-clockwise, 2 x m): min over its edges of the centre's distance to the edge's
/// line, > 0 inside, 0 on an edge, < 0 outside (then a lower bound of minus the distance);
/// -inf for fewer than 3 vertices.
double centre_margin(const Eigen::Matrix2Xd& support);

/// Foothold search (place_walk_on_terrain): each footstep may move horizontally by up to
/// @c radius (m) to a placement whose support holds its centre better.
struct FootholdSearch {
  double radius = 0.0;   ///< m, >= 0; 0: the footsteps stay where planned
  double spacing = 0.01; ///< m, > 0: candidates on a square grid of this spacing in the disk
  /// rad, > 0: a candidate tilted more than this (and more than the plan's own placement) is
  /// left out: a sole bridging a step's edge holds its centre well but rests on the edge line
  double max_tilt = 0.05;
};

/// The angle (rad) between a placement's sole normal and the vertical, acos(cos(pitch) cos(roll)).
double footstep_tilt(const Footstep& step);

/// Places @p step as place_on_terrain does, at the candidate position (step.x + dx, step.y + dy),
/// (dx, dy) on the grid of @p search in the disk of its radius, whose support holds the centre
/// best: the largest min(centre_margin(support), zmp_margin), ties (to 1e-9 m) to the nearest
/// to the plan. Candidates whose centre margin reaches @p zmp_margin are all good enough: the
/// nearest of them is kept, so a ground where the plan's own placement is good leaves it there.
/// A candidate farther than @p max_step_length (m) from @p swing_from (the swing foot's last
/// placement, x, y), or tilted more than max(search.max_tilt, the plan's placement's tilt)
/// (footstep_tilt), is left out; the plan's own position never is. (2 floor(r / s) + 1)^2
/// candidates at most, each a place_on_terrain.
Footstep place_on_foothold(const contact::Terrain& terrain, const Footstep& step,
                           const SolePoints& points, double zmp_margin,
                           const FootholdSearch& search, const Eigen::Vector2d& swing_from,
                           double max_step_length);

/// The lift fraction f of the swing from @p from onto @p to (Footstep::lift_fraction) on
/// @p terrain: the smallest f in [0, 0.45] (bisection to 1e-3; the sole is higher at every point
/// of its path the larger f) for which the sole's footprint stays above the ground along the
/// swing of make_footstep_plan (201 instants of the single support): with z(tau) the sole
/// centre's height, z_n the nearer placement's (from.z for tau < 1/2, else to.z) and R(tau) its
/// orientation, every point q of a grid of about 1 cm over the bounding box of @p points
/// satisfies
///   z + [R q]_z - h(x + [R q]_x, y + [R q]_y) >= min(walk.swing_ground_margin, z - z_n).
/// At a placement the sole rests with its lowest points on the ground, so the condition binds
/// only where the footprint moves over other ground: 0 on flat ground, > 0 where a toe starts
/// near a riser, on a step down, and where a bump lies in the path.
/// @throws std::runtime_error when f = 0.45 does not clear the ground (raise Step height).
double swing_lift_fraction(const contact::Terrain& terrain, const Footstep& from,
                           const Footstep& to, const SolePoints& points,
                           const WalkingParameters& walk);

/// place_on_terrain for the initial soles and place_on_foothold for every footstep of @p walk
/// (modified in place; the initial soles are where the robot stands, not moved; the steps stay
/// within walk.max_step_length), then each footstep's swing_lift_fraction from the same foot's
/// previous placement.
void place_walk_on_terrain(const contact::Terrain& terrain, const SolePoints& points,
                           double zmp_margin, WalkingParameters& walk,
                           const FootholdSearch& search = {});

} // namespace plantar::walking
