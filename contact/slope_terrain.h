#pragma once
// An inclined plane: the plane z = z0 through (x0, y0, z0) turned by the angle alpha about the
// horizontal axis a = (cos psi, sin psi, 0) through that point (right hand: alpha > 0 about e_x
// raises the ground towards +y). Its normal is R(a, alpha) e_z, so
//   h(x, y) = z0 + tan(alpha) (-a_y (x - x0) + a_x (y - y0)),
//   grad h = tan(alpha) (-a_y, a_x).

#include "contact/terrain.h"

namespace plantar::contact {

class SlopeTerrain final : public Terrain {
public:
  /// @p angle alpha (rad, (-pi/2, pi/2)), @p axis_heading psi (rad, finite: the axis' angle
  /// from e_x), @p point (x0, y0, z0) on the plane (m, finite). Throws std::invalid_argument
  /// naming the argument, value and range.
  SlopeTerrain(double angle, double axis_heading, const Eigen::Vector3d& point);
  double height(double x, double y) const override {
    return point_.z() + slope_.dot(Eigen::Vector2d(x - point_.x(), y - point_.y()));
  }
  Eigen::Vector2d gradient(double, double) const override { return slope_; }

private:
  Eigen::Vector3d point_;
  Eigen::Vector2d slope_; // tan(alpha) (-a_y, a_x)
};

} // namespace plantar::contact
