#include "contact/step_terrain.h"

#include <cmath>
#include <sstream>
#include <stdexcept>

namespace plantar::contact {

StepTerrain::StepTerrain(double rise, double heading, const Eigen::Vector2d& edge_point,
                         double level, double width)
    : rise_(rise), level_(level), width_(width), edge_point_(edge_point) {
  std::ostringstream msg;
  if (!std::isfinite(rise))
    msg << "StepTerrain: rise = " << rise << " m, allowed finite";
  else if (!std::isfinite(heading))
    msg << "StepTerrain: heading = " << heading << " rad, allowed finite";
  else if (!edge_point.allFinite() || !std::isfinite(level))
    msg << "StepTerrain: edge point (" << edge_point.transpose() << ") and level " << level
        << " m, allowed finite";
  else if (!(width >= 0.0) || !std::isfinite(width))
    msg << "StepTerrain: width = " << width << " m, allowed [0, inf)";
  if (!msg.str().empty())
    throw std::invalid_argument(msg.str());
  direction_ = Eigen::Vector2d(std::cos(heading), std::sin(heading));
}

double StepTerrain::height(double x, double y) const {
  const double s = direction_.dot(Eigen::Vector2d(x, y) - edge_point_);
  if (width_ == 0.0)
    return level_ + (s >= 0.0 ? rise_ : 0.0);
  const double t = s / width_ + 0.5;
  if (t <= 0.0)
    return level_;
  if (t >= 1.0)
    return level_ + rise_;
  return level_ + rise_ * t * t * (3.0 - 2.0 * t);
}

Eigen::Vector2d StepTerrain::gradient(double x, double y) const {
  if (width_ == 0.0)
    return Eigen::Vector2d::Zero();
  const double s = direction_.dot(Eigen::Vector2d(x, y) - edge_point_);
  const double t = s / width_ + 0.5;
  if (t <= 0.0 || t >= 1.0)
    return Eigen::Vector2d::Zero();
  return (rise_ * 6.0 * t * (1.0 - t) / width_) * direction_;
}

} // namespace plantar::contact
