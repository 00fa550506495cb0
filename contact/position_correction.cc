#include "contact/position_correction.h"

#include <algorithm>
#include <cmath>
#include <sstream>
#include <stdexcept>

namespace plantar::contact {

void NormalBiasParameters::validate() const {
  auto bad = [](const char* name, double value, const char* range) {
    std::ostringstream msg;
    msg << "NormalBiasParameters." << name << " = " << value << ", allowed " << range;
    throw std::invalid_argument(msg.str());
  };
  if (!(restitution >= 0.0 && restitution <= 1.0))
    bad("restitution", restitution, "[0, 1]");
  if (!(restitution_threshold >= 0.0) || !std::isfinite(restitution_threshold))
    bad("restitution_threshold", restitution_threshold, "[0, inf)");
  if (!(position_correction > 0.0 && position_correction <= 1.0))
    bad("position_correction", position_correction, "(0, 1]");
  if (!(penetration_slop >= 0.0) || !std::isfinite(penetration_slop))
    bad("penetration_slop", penetration_slop, "[0, inf)");
}

double normal_bias(double gap, double normal_velocity_before, double dt,
                   const NormalBiasParameters& parameters) {
  if (!(dt > 0.0) || !std::isfinite(dt)) {
    std::ostringstream msg;
    msg << "normal_bias: dt = " << dt << " s, allowed (0, inf)";
    throw std::invalid_argument(msg.str());
  }
  const double e = std::abs(normal_velocity_before) >= parameters.restitution_threshold
                       ? parameters.restitution
                       : 0.0;
  const double correction =
      parameters.position_correction * std::min(gap + parameters.penetration_slop, 0.0) / dt;
  if (e > 0.0 && normal_velocity_before < 0.0) // impact with bounce (eq. 5)
    return std::min(e * normal_velocity_before, correction);
  if (gap > 0.0) // speculative: may close the remaining gap this step, no more
    return gap / dt;
  return correction;
}

} // namespace plantar::contact
