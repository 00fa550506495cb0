#include "contact/terrain.h"

#include <Eigen/Geometry>
#include <cmath>

namespace plantar::contact {

Eigen::Vector3d terrain_normal(const Eigen::Vector2d& slope) {
  const double inverse_norm = 1.0 / std::sqrt(1.0 + slope.squaredNorm());
  return Eigen::Vector3d(-slope.x() * inverse_norm, -slope.y() * inverse_norm, inverse_norm);
}

Eigen::Matrix3d terrain_frame(const Eigen::Vector2d& slope) {
  const Eigen::Vector3d n = terrain_normal(slope);
  // e_x - n_x n, norm^2 = 1 - n_x^2 (> 0 since n_z > 0).
  const Eigen::Vector3d t1 = Eigen::Vector3d(1.0 - n.x() * n.x(), -n.x() * n.y(), -n.x() * n.z()) /
                             std::sqrt(1.0 - n.x() * n.x());
  Eigen::Matrix3d frame;
  frame.col(0) = n;
  frame.col(1) = t1;
  frame.col(2) = n.cross(t1);
  return frame;
}

TerrainContact terrain_contact(const Terrain& terrain, const Eigen::Vector3d& point) {
  TerrainContact out;
  const Eigen::Vector2d slope = terrain.gradient(point.x(), point.y());
  out.frame = terrain_frame(slope);
  out.gap = (point.z() - terrain.height(point.x(), point.y())) * out.frame(2, 0);
  return out;
}

double terrain_gap(const Terrain& terrain, const Eigen::Vector3d& point) {
  const Eigen::Vector2d slope = terrain.gradient(point.x(), point.y());
  return (point.z() - terrain.height(point.x(), point.y())) * terrain_normal(slope).z();
}

} // namespace plantar::contact
