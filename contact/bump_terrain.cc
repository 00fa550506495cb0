#include "contact/bump_terrain.h"

#include <cmath>
#include <sstream>
#include <stdexcept>

namespace plantar::contact {

BumpTerrain::BumpTerrain(double amplitude, double wavelength_x, double wavelength_y, double level)
    : amplitude_(amplitude), level_(level) {
  std::ostringstream msg;
  if (!std::isfinite(amplitude) || !std::isfinite(level))
    msg << "BumpTerrain: amplitude = " << amplitude << " m, level = " << level
        << " m, allowed finite";
  else if (!(wavelength_x >= 0.0) || !std::isfinite(wavelength_x))
    msg << "BumpTerrain: wavelength x = " << wavelength_x << " m, allowed (0, inf) or 0 (none)";
  else if (!(wavelength_y >= 0.0) || !std::isfinite(wavelength_y))
    msg << "BumpTerrain: wavelength y = " << wavelength_y << " m, allowed (0, inf) or 0 (none)";
  if (!msg.str().empty())
    throw std::invalid_argument(msg.str());
  wave_x_ = wavelength_x > 0.0 ? 2.0 * M_PI / wavelength_x : 0.0;
  wave_y_ = wavelength_y > 0.0 ? 2.0 * M_PI / wavelength_y : 0.0;
}

double BumpTerrain::height(double x, double y) const {
  return level_ + amplitude_ * std::cos(wave_x_ * x) * std::cos(wave_y_ * y);
}

Eigen::Vector2d BumpTerrain::gradient(double x, double y) const {
  const double cx = std::cos(wave_x_ * x), cy = std::cos(wave_y_ * y);
  return Eigen::Vector2d(-amplitude_ * wave_x_ * std::sin(wave_x_ * x) * cy,
                         -amplitude_ * wave_y_ * cx * std::sin(wave_y_ * y));
}

} // namespace plantar::contact
