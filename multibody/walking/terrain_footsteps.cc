#include "multibody/walking/terrain_footsteps.h"

#include "multibody/walking/support_polygon.h"

#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>

namespace plantar::walking {

SolePoints sole_grid(double length, double width, int m) {
  if (!(length > 0) || !(width > 0) || m < 2)
    throw std::invalid_argument("sole_grid: length = " + std::to_string(length) +
                                " m and width = " + std::to_string(width) +
                                " m must be > 0, m = " + std::to_string(m) + " >= 2");
  SolePoints points(2, m * m);
  for (int i = 0; i < m; ++i)
    for (int j = 0; j < m; ++j)
      points.col(i * m + j) << length * (double(i) / (m - 1) - 0.5),
          width * (double(j) / (m - 1) - 0.5);
  return points;
}

namespace {

/// The lowest plane (a, b, c) at the centre, z = a + b x + c y, with h_i <= z(xy_i) for every
/// point: over the triples of points whose triangle holds the centre (0, 0); of planes equally
/// low there (to the height tolerance: a point at the centre on a peak) the least tilted.
/// a = inf if none.
/// @p triple receives the three points' indices.
Eigen::Vector3d upper_facet(const SolePoints& xy, const Eigen::VectorXd& h,
                            Eigen::Vector3i& triple) {
  const int n = static_cast<int>(xy.cols());
  const double scale = xy.cwiseAbs().maxCoeff();
  const double area_tolerance = 1e-12 * scale * scale;
  const double height_tolerance = 1e-12 * std::max(1.0, h.cwiseAbs().maxCoeff());
  Eigen::Vector3d best(std::numeric_limits<double>::infinity(), 0, 0);
  for (int i = 0; i < n; ++i)
    for (int j = i + 1; j < n; ++j)
      for (int k = j + 1; k < n; ++k) {
        const Eigen::Vector2d a = xy.col(i), b = xy.col(j), c = xy.col(k);
        const double area = (b - a).x() * (c - a).y() - (b - a).y() * (c - a).x();
        if (std::abs(area) < area_tolerance)
          continue;
        // Barycentric coordinates of the centre (0, 0).
        const double l1 = (b.x() * c.y() - c.x() * b.y()) / area;
        const double l2 = (c.x() * a.y() - a.x() * c.y()) / area;
        const double l3 = 1.0 - l1 - l2;
        if (l1 < -1e-12 || l2 < -1e-12 || l3 < -1e-12)
          continue;
        const double centre = l1 * h[i] + l2 * h[j] + l3 * h[k];
        if (centre > best[0] + height_tolerance)
          continue;
        Eigen::Matrix2d d;
        d << (b - a).x(), (b - a).y(), (c - a).x(), (c - a).y();
        const Eigen::Vector2d slope = d.inverse() * Eigen::Vector2d(h[j] - h[i], h[k] - h[i]);
        // Planes as low at the centre (a point of the sole on a peak under it) tie: the least
        // tilted is kept.
        if (centre >= best[0] - height_tolerance &&
            slope.squaredNorm() >= best.tail<2>().squaredNorm())
          continue;
        bool above = true;
        for (int m = 0; m < n && above; ++m)
          above = h[m] <= centre + slope.dot(xy.col(m)) + height_tolerance;
        if (above) {
          best << centre, slope.x(), slope.y();
          triple << i, j, k;
        }
      }
  return best;
}

} // namespace

Footstep place_on_terrain(const contact::Terrain& terrain, const Footstep& step,
                          const SolePoints& points, double zmp_margin) {
  const int n = static_cast<int>(points.cols());
  if (n < 3)
    throw std::invalid_argument("place_on_terrain: " + std::to_string(n) +
                                " sole points, at least 3 needed");
  const Eigen::Matrix2d yaw = Eigen::Rotation2Dd(step.yaw).toRotationMatrix();
  Footstep placed = step;
  SolePoints xy = points; // the points' horizontal positions in the yawed frame
  Eigen::VectorXd h(n);
  Eigen::Vector3i triple(-1, -1, -1);
  // Fixed point in the tilt: the tilted sole's points move horizontally by O(tilt^2).
  for (int iteration = 0; iteration < 20; ++iteration) {
    for (int i = 0; i < n; ++i) {
      const Eigen::Vector2d w = Eigen::Vector2d(step.x, step.y) + yaw * xy.col(i);
      h[i] = terrain.height(w.x(), w.y());
    }
    const Eigen::Vector3d facet = upper_facet(xy, h, triple);
    if (!std::isfinite(facet[0]))
      throw std::invalid_argument("place_on_terrain: the sole centre is not inside the convex "
                                  "hull of its points");
    const double norm = std::sqrt(1.0 + facet[1] * facet[1] + facet[2] * facet[2]);
    const double pitch = -std::atan(facet[1]), roll = std::asin(facet[2] / norm);
    const bool converged =
        iteration > 0 && std::abs(pitch - placed.pitch) + std::abs(roll - placed.roll) < 1e-14;
    placed.pitch = pitch;
    placed.roll = roll;
    placed.z = facet[0];
    if (converged)
      break;
    const Eigen::Matrix3d tilt = footstep_rotation(0.0, pitch, roll);
    for (int i = 0; i < n; ++i)
      xy.col(i) = (tilt * Eigen::Vector3d(points(0, i), points(1, i), 0.0)).head<2>();
  }
  // The tilted points: move the plane so that the lowest is on the ground (the iteration's
  // last change, round-off).
  const Eigen::Matrix3d rotation = footstep_rotation(placed.yaw, placed.pitch, placed.roll);
  Eigen::VectorXd gap(n);
  for (int i = 0; i < n; ++i) {
    const Eigen::Vector3d point = Eigen::Vector3d(placed.x, placed.y, placed.z) +
                                  rotation * Eigen::Vector3d(points(0, i), points(1, i), 0.0);
    gap[i] = point.z() - terrain.height(point.x(), point.y());
  }
  const double lowest = gap.minCoeff();
  placed.z -= lowest;
  gap.array() -= lowest;
  // The support: the facet's three points and any other on the ground; the ZMP target on it.
  const double on_ground = 1e-9 * std::max(1.0, std::abs(placed.z));
  SolePoints touching(2, n);
  int m = 0;
  for (int i = 0; i < n; ++i)
    if (gap[i] <= on_ground || i == triple[0] || i == triple[1] || i == triple[2])
      touching.col(m++) = points.col(i);
  placed.support = convex_hull(touching.leftCols(m));
  placed.zmp_x = placed.zmp_y = 0.0;
  if (placed.support.cols() >= 3) {
    const Eigen::Vector2d zmp =
        nearest_in_polygon(Eigen::Vector2d::Zero(), placed.support, zmp_margin);
    placed.zmp_x = zmp.x();
    placed.zmp_y = zmp.y();
  }
  return placed;
}

double footstep_tilt(const Footstep& step) {
  return std::acos(std::clamp(std::cos(step.pitch) * std::cos(step.roll), -1.0, 1.0));
}

double centre_margin(const Eigen::Matrix2Xd& support) {
  const int m = static_cast<int>(support.cols());
  if (m < 3)
    return -std::numeric_limits<double>::infinity();
  double margin = std::numeric_limits<double>::infinity();
  for (int i = 0; i < m; ++i) {
    const Eigen::Vector2d a = support.col(i), edge = support.col((i + 1) % m) - a;
    const double length = edge.norm();
    if (length > 0.0) // (0 - a) x edge, left of the edge > 0
      margin = std::min(margin, (edge.y() * a.x() - edge.x() * a.y()) / length);
  }
  return margin;
}

Footstep place_on_foothold(const contact::Terrain& terrain, const Footstep& step,
                           const SolePoints& points, double zmp_margin,
                           const FootholdSearch& search, const Eigen::Vector2d& swing_from,
                           double max_step_length) {
  if (!(search.radius >= 0.0) || !(search.spacing > 0.0) || !(search.max_tilt > 0.0))
    throw std::invalid_argument("place_on_foothold: radius = " + std::to_string(search.radius) +
                                " m must be >= 0, spacing = " + std::to_string(search.spacing) +
                                " m > 0 and max_tilt = " + std::to_string(search.max_tilt) +
                                " rad > 0");
  const Footstep own = place_on_terrain(terrain, step, points, zmp_margin);
  const double max_tilt = std::max(search.max_tilt, footstep_tilt(own));
  const int k = static_cast<int>(std::floor(search.radius / search.spacing + 1e-9));
  Footstep best;
  double best_score = -std::numeric_limits<double>::infinity(), best_distance = 0.0;
  for (int i = -k; i <= k; ++i)
    for (int j = -k; j <= k; ++j) {
      const double dx = i * search.spacing, dy = j * search.spacing;
      const double distance = std::hypot(dx, dy);
      if ((i != 0 || j != 0) && (distance > search.radius + 1e-12 ||
                                 std::hypot(step.x + dx - swing_from.x(),
                                            step.y + dy - swing_from.y()) > max_step_length))
        continue;
      Footstep candidate = step;
      candidate.x += dx;
      candidate.y += dy;
      candidate = i == 0 && j == 0 ? own : place_on_terrain(terrain, candidate, points, zmp_margin);
      if (footstep_tilt(candidate) > max_tilt + 1e-12)
        continue;
      const double score = std::min(centre_margin(candidate.support), zmp_margin);
      if (score > best_score + 1e-9 ||
          (std::abs(score - best_score) <= 1e-9 && distance < best_distance)) {
        best = candidate;
        best_score = score;
        best_distance = distance;
      }
    }
  return best;
}

namespace {

/// Whether the swing from @p from onto @p to with lift fraction @p f (make_footstep_plan's,
/// swing_sample) keeps every point of @p footprint (sole frame) above the ground as
/// swing_lift_fraction states.
bool swing_clears(const contact::Terrain& terrain, const Footstep& from, Footstep to,
                  const SolePoints& footprint, const WalkingParameters& walk, double f) {
  to.lift_fraction = f;
  const int n = 200;
  for (int k = 0; k <= n; ++k) {
    const double tau = double(k) / n;
    const SwingSample swing = swing_sample(walk, from, to, tau);
    if (swing.progress <= 0.0 || swing.progress >= 1.0)
      continue; // on its own placement, lifted: its lowest points rest on the ground below
    const Footstep& sole = swing.sole;
    const Eigen::Matrix3d rotation = footstep_rotation(sole.yaw, sole.pitch, sole.roll);
    const Eigen::Vector3d centre(sole.x, sole.y, sole.z);
    // Near a placement, as high above it as the swing has lifted the sole.
    const double required =
        std::min(walk.swing_ground_margin, sole.z - (tau < 0.5 ? from.z : to.z));
    for (Eigen::Index i = 0; i < footprint.cols(); ++i) {
      const Eigen::Vector3d p =
          centre + rotation * Eigen::Vector3d(footprint(0, i), footprint(1, i), 0.0);
      if (p.z() - terrain.height(p.x(), p.y()) < required - 1e-9)
        return false;
    }
  }
  return true;
}

} // namespace

double swing_lift_fraction(const contact::Terrain& terrain, const Footstep& from,
                           const Footstep& to, const SolePoints& points,
                           const WalkingParameters& walk) {
  if (points.cols() < 1)
    throw std::invalid_argument("swing_lift_fraction: no sole points");
  // A grid of about 1 cm over the points' bounding box.
  const Eigen::Vector2d low = points.rowwise().minCoeff(), high = points.rowwise().maxCoeff();
  const int nx = std::max(2, static_cast<int>(std::ceil((high.x() - low.x()) / 0.01)) + 1);
  const int ny = std::max(2, static_cast<int>(std::ceil((high.y() - low.y()) / 0.01)) + 1);
  SolePoints footprint(2, nx * ny);
  for (int i = 0; i < nx; ++i)
    for (int j = 0; j < ny; ++j)
      footprint.col(i * ny + j) << low.x() + (high.x() - low.x()) * i / (nx - 1),
          low.y() + (high.y() - low.y()) * j / (ny - 1);
  if (swing_clears(terrain, from, to, footprint, walk, 0.0))
    return 0.0;
  const double most = 0.45;
  if (!swing_clears(terrain, from, to, footprint, walk, most))
    throw std::runtime_error(
        "the swing from (" + std::to_string(from.x) + ", " + std::to_string(from.y) + ") to (" +
        std::to_string(to.x) + ", " + std::to_string(to.y) +
        ") m does not clear the ground between them by Walking/Swing ground margin = " +
        std::to_string(walk.swing_ground_margin) + " m even lifting the foot over " +
        std::to_string(most) + " of its swing: raise Walking/Step height (" +
        std::to_string(walk.step_height) + " m)");
  double lower = 0.0, upper = most;
  while (upper - lower > 1e-3) {
    const double middle = 0.5 * (lower + upper);
    (swing_clears(terrain, from, to, footprint, walk, middle) ? upper : lower) = middle;
  }
  return upper;
}

void place_walk_on_terrain(const contact::Terrain& terrain, const SolePoints& points,
                           double zmp_margin, WalkingParameters& walk,
                           const FootholdSearch& search) {
  walk.initial_right = place_on_terrain(terrain, walk.initial_right, points, zmp_margin);
  walk.initial_left = place_on_terrain(terrain, walk.initial_left, points, zmp_margin);
  Footstep right = walk.initial_right, left = walk.initial_left;
  for (std::size_t i = 0; i < walk.footsteps.size(); ++i) {
    Footstep& from = (i % 2 == 0) == walk.right_foot_first ? right : left;
    Footstep& step = walk.footsteps[i];
    step = place_on_foothold(terrain, step, points, zmp_margin, search,
                             Eigen::Vector2d(from.x, from.y), walk.max_step_length);
    step.lift_fraction = swing_lift_fraction(terrain, from, step, points, walk);
    from = step;
  }
}

} // namespace plantar::walking
