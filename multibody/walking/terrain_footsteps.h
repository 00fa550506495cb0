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
/// is the lowest one at the centre with h_i <= a + b x'_i + c y'_i for every point: the facet of
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

/// place_on_terrain for the initial soles and every footstep of @p walk (modified in place).
void place_walk_on_terrain(const contact::Terrain& terrain, const SolePoints& points,
                           double zmp_margin, WalkingParameters& walk);

} // namespace plantar::walking
