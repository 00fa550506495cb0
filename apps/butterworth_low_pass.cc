#include "apps/butterworth_low_pass.h"

#include <cmath>
#include <sstream>
#include <stdexcept>

namespace plantar::app {

ButterworthLowPass make_butterworth_low_pass(double cutoff, double period, const char* parameter) {
  if (!(period > 0) || !std::isfinite(period)) {
    std::ostringstream msg;
    msg << parameter << ": sample period " << period << " s must be > 0";
    throw std::invalid_argument(msg.str());
  }
  const double nyquist = 0.5 / period;
  if (!(cutoff >= 0 && cutoff < nyquist)) {
    std::ostringstream msg;
    msg << parameter << " = " << cutoff << " Hz is outside [0, " << nyquist
        << ") Hz (below the Nyquist frequency 1 / (2 dt), dt = " << period << " s; 0: raw)";
    throw std::invalid_argument(msg.str());
  }
  ButterworthLowPass f;
  if (cutoff == 0)
    return f;
  const double k = std::tan(M_PI * cutoff * period), k2 = k * k;
  const double d = 1.0 + std::sqrt(2.0) * k + k2;
  f.b0 = k2 / d;
  f.b1 = 2.0 * f.b0;
  f.b2 = f.b0;
  f.a1 = 2.0 * (k2 - 1.0) / d;
  f.a2 = (1.0 - std::sqrt(2.0) * k + k2) / d;
  return f;
}

} // namespace plantar::app
