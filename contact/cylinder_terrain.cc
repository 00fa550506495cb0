#include "contact/cylinder_terrain.h"

#include <algorithm>
#include <cmath>
#include <sstream>
#include <stdexcept>

namespace plantar::contact {

CylinderTerrain::CylinderTerrain(double radius, double rise, double heading,
                                 const Eigen::Vector2d& axis_point, double level)
    : radius_(radius), rise_(rise), level_(level), axis_point_(axis_point) {
  std::ostringstream msg;
  if (!(radius > 0.0) || !std::isfinite(radius))
    msg << "CylinderTerrain: radius = " << radius << " m, allowed (0, inf)";
  else if (!(rise > 0.0 && rise <= radius))
    msg << "CylinderTerrain: rise = " << rise << " m, allowed (0, radius = " << radius << "]";
  else if (!std::isfinite(heading) || !axis_point.allFinite() || !std::isfinite(level))
    msg << "CylinderTerrain: heading " << heading << " rad, axis point (" << axis_point.transpose()
        << ") m, level " << level << " m, allowed finite";
  if (!msg.str().empty())
    throw std::invalid_argument(msg.str());
  across_ = Eigen::Vector2d(-std::sin(heading), std::cos(heading));
  half_width_ = std::sqrt(radius * radius - (radius - rise) * (radius - rise));
}

double CylinderTerrain::height(double x, double y) const {
  const double d = distance(x, y);
  if (std::abs(d) >= half_width_)
    return level_;
  return level_ + std::max(0.0, std::sqrt(radius_ * radius_ - d * d) - (radius_ - rise_));
}

Eigen::Vector2d CylinderTerrain::gradient(double x, double y) const {
  const double d = distance(x, y);
  if (std::abs(d) >= half_width_)
    return Eigen::Vector2d::Zero();
  const double root = std::max(std::sqrt(radius_ * radius_ - d * d), 1e-6 * radius_);
  return (-d / root) * across_;
}

} // namespace plantar::contact
