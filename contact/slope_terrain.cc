#include "contact/slope_terrain.h"

#include <cmath>
#include <sstream>
#include <stdexcept>

namespace plantar::contact {

SlopeTerrain::SlopeTerrain(double angle, double axis_heading, const Eigen::Vector3d& point)
    : point_(point) {
  std::ostringstream msg;
  if (!(std::abs(angle) < 0.5 * M_PI))
    msg << "SlopeTerrain: angle = " << angle << " rad, allowed (-pi/2, pi/2)";
  else if (!std::isfinite(axis_heading))
    msg << "SlopeTerrain: axis heading = " << axis_heading << " rad, allowed finite";
  else if (!point.allFinite())
    msg << "SlopeTerrain: point (" << point.transpose() << ") m, allowed finite";
  if (!msg.str().empty())
    throw std::invalid_argument(msg.str());
  slope_ = std::tan(angle) * Eigen::Vector2d(-std::sin(axis_heading), std::cos(axis_heading));
}

} // namespace plantar::contact
