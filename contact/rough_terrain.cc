#include "contact/rough_terrain.h"

#include <algorithm>
#include <cmath>
#include <random>
#include <sstream>
#include <stdexcept>

namespace plantar::contact {

void RoughTerrainParameters::validate() const {
  std::ostringstream msg;
  if (!(rms >= 0.0 && rms <= 1.0))
    msg << "RMS height = " << rms << " m, allowed [0, 1]";
  else if (!(correlation_length > 0.0 && correlation_length <= 100.0))
    msg << "Correlation length = " << correlation_length << " m, allowed (0, 100]";
  else if (modes < 1 || modes > 100000)
    msg << "Modes = " << modes << ", allowed [1, 100000]";
  else if (!(size_x > 0.0 && size_x <= 1000.0) || !(size_y > 0.0 && size_y <= 1000.0))
    msg << "Size = " << size_x << " x " << size_y << " m, allowed (0, 1000] each";
  else if (!std::isfinite(centre_x) || !std::isfinite(centre_y) || !std::isfinite(level))
    msg << "centre (" << centre_x << ", " << centre_y << ") and level " << level
        << " m, allowed finite";
  else {
    const double spacing = correlation_length / 8.0;
    const double nodes = (std::ceil(size_x / spacing) + 1) * (std::ceil(size_y / spacing) + 1);
    if (nodes > 4e6)
      msg << "Size " << size_x << " x " << size_y << " m at spacing l/8 = " << spacing
          << " m gives " << nodes << " grid nodes, allowed <= 4e6 (larger l or smaller size)";
  }
  if (!msg.str().empty())
    throw std::invalid_argument("RoughTerrain: " + msg.str());
}

RoughTerrain::RoughTerrain(const RoughTerrainParameters& parameters) : parameters_(parameters) {
  parameters.validate();
  std::mt19937_64 engine(parameters.seed);
  auto uniform = [&engine] { return (static_cast<double>(engine() >> 11) + 0.5) * 0x1.0p-53; };
  const int n = parameters.modes;
  const double deviation = std::sqrt(2.0) / parameters.correlation_length;
  wave_.resize(n);
  phase_.resize(n);
  for (int j = 0; j < n; ++j) { // Box-Muller: two normals from two uniforms
    const double radius = std::sqrt(-2.0 * std::log(uniform()));
    const double angle = 2.0 * M_PI * uniform();
    wave_[j] = deviation * radius * Eigen::Vector2d(std::cos(angle), std::sin(angle));
    phase_[j] = 2.0 * M_PI * uniform();
  }
  amplitude_ = parameters.rms * std::sqrt(2.0 / n);
  spacing_ = parameters.correlation_length / 8.0;
  nx_ = static_cast<int>(std::ceil(parameters.size_x / spacing_)) + 1;
  ny_ = static_cast<int>(std::ceil(parameters.size_y / spacing_)) + 1;
  x0_ = parameters.centre_x - 0.5 * (nx_ - 1) * spacing_;
  y0_ = parameters.centre_y - 0.5 * (ny_ - 1) * spacing_;
  const std::size_t size = static_cast<std::size_t>(nx_) * ny_;
  h_.assign(size, 0.0);
  hx_.assign(size, 0.0);
  hy_.assign(size, 0.0);
  hxy_.assign(size, 0.0);
  for (int j = 0; j < ny_; ++j) {
    for (int i = 0; i < nx_; ++i) {
      const Eigen::Vector2d x(x0_ + i * spacing_, y0_ + j * spacing_);
      double h = 0, hx = 0, hy = 0, hxy = 0;
      for (int m = 0; m < n; ++m) {
        const double argument = wave_[m].dot(x) + phase_[m];
        const double c = std::cos(argument), s = std::sin(argument);
        h += c;
        hx -= wave_[m].x() * s;
        hy -= wave_[m].y() * s;
        hxy -= wave_[m].x() * wave_[m].y() * c;
      }
      const std::size_t at = static_cast<std::size_t>(i) + static_cast<std::size_t>(nx_) * j;
      h_[at] = amplitude_ * h;
      hx_[at] = amplitude_ * hx;
      hy_[at] = amplitude_ * hy;
      hxy_[at] = amplitude_ * hxy;
    }
  }
}

double RoughTerrain::mode_height(double x, double y) const {
  double h = 0;
  for (std::size_t m = 0; m < wave_.size(); ++m)
    h += std::cos(wave_[m].x() * x + wave_[m].y() * y + phase_[m]);
  return parameters_.level + amplitude_ * h;
}

bool RoughTerrain::locate(double x, double y, int& i, int& j, double& u, double& v) const {
  const double gx = (x - x0_) / spacing_, gy = (y - y0_) / spacing_;
  const bool inside = gx >= 0.0 && gx <= nx_ - 1 && gy >= 0.0 && gy <= ny_ - 1;
  const double cx = std::clamp(gx, 0.0, static_cast<double>(nx_ - 1));
  const double cy = std::clamp(gy, 0.0, static_cast<double>(ny_ - 1));
  i = std::min(static_cast<int>(cx), nx_ - 2);
  j = std::min(static_cast<int>(cy), ny_ - 2);
  u = cx - i;
  v = cy - j;
  return inside;
}

double RoughTerrain::interpolate(int i, int j, double u, double v, int derivative) const {
  // Cubic Hermite bases on [0, 1]: value bases p0, p1, slope bases q0, q1 (and derivatives).
  auto bases = [](double t, bool derivative_of, double out[4]) {
    if (!derivative_of) {
      out[0] = 1 - 3 * t * t + 2 * t * t * t;
      out[1] = 3 * t * t - 2 * t * t * t;
      out[2] = t - 2 * t * t + t * t * t;
      out[3] = -t * t + t * t * t;
    } else {
      out[0] = -6 * t + 6 * t * t;
      out[1] = 6 * t - 6 * t * t;
      out[2] = 1 - 4 * t + 3 * t * t;
      out[3] = -2 * t + 3 * t * t;
    }
  };
  double bu[4], bv[4];
  bases(u, derivative == 1, bu);
  bases(v, derivative == 2, bv);
  const double d = spacing_;
  double sum = 0;
  for (int b = 0; b < 2; ++b) {
    for (int a = 0; a < 2; ++a) {
      const std::size_t at =
          static_cast<std::size_t>(i + a) + static_cast<std::size_t>(nx_) * (j + b);
      sum += bu[a] * bv[b] * h_[at] + d * bu[2 + a] * bv[b] * hx_[at] +
             d * bu[a] * bv[2 + b] * hy_[at] + d * d * bu[2 + a] * bv[2 + b] * hxy_[at];
    }
  }
  return derivative == 0 ? sum : sum / d;
}

double RoughTerrain::height(double x, double y) const {
  int i, j;
  double u, v;
  locate(x, y, i, j, u, v);
  return parameters_.level + interpolate(i, j, u, v, 0);
}

Eigen::Vector2d RoughTerrain::gradient(double x, double y) const {
  int i, j;
  double u, v;
  if (!locate(x, y, i, j, u, v))
    return Eigen::Vector2d::Zero();
  return Eigen::Vector2d(interpolate(i, j, u, v, 1), interpolate(i, j, u, v, 2));
}

} // namespace plantar::contact
