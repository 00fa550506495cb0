#pragma once
// A cylindrical bump on flat ground z = z0: a horizontal cylinder of radius R whose axis (heading
// psi, through (x0, y0)) lies R - b below the top, so that the bump rises b (0 < b <= R) above the
// ground. With d the horizontal distance from the axis' vertical plane,
//   d = -sin(psi) (x - x0) + cos(psi) (y - y0),
//   h = z0 + max(0, sqrt(R^2 - d^2) - (R - b)),
//   grad h = -d / sqrt(R^2 - d^2) (-sin psi, cos psi) on the bump, 0 off it.
// The foot of the bump (|d| = sqrt(R^2 - (R - b)^2)) is a kink: the gradient jumps there
// (from 0 to the cylinder's slope; for b = R a vertical tangent, where the gradient is capped at
// the value 1e-6 R inside the foot).

#include "contact/terrain.h"

namespace plantar::contact {

class CylinderTerrain final : public Terrain {
public:
  /// @p radius R (m, > 0), @p rise b (m, (0, R]), @p heading psi (rad), @p axis_point (x0, y0)
  /// (m), @p level z0 (m); finite. Throws std::invalid_argument naming the argument.
  CylinderTerrain(double radius, double rise, double heading, const Eigen::Vector2d& axis_point,
                  double level);
  double height(double x, double y) const override;
  Eigen::Vector2d gradient(double x, double y) const override;
  /// Half width sqrt(R^2 - (R - b)^2) of the bump (m).
  double half_width() const { return half_width_; }

private:
  double distance(double x, double y) const {
    return across_.dot(Eigen::Vector2d(x, y) - axis_point_);
  }
  double radius_, rise_, level_, half_width_;
  Eigen::Vector2d across_, axis_point_; // (-sin psi, cos psi)
};

} // namespace plantar::contact
