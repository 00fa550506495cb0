#pragma once
// Sinusoidal bumps (an egg crate):
//   h(x, y) = z0 + A cos(2 pi x / L_x) cos(2 pi y / L_y),
// amplitude A, wavelengths L_x, L_y; a wavelength of 0 stands for infinity (the factor is 1: a
// corrugation along the other axis only).
//   grad h = -A (2 pi / L_x sin(2 pi x / L_x) cos(2 pi y / L_y),
//               2 pi / L_y cos(2 pi x / L_x) sin(2 pi y / L_y)).

#include "contact/terrain.h"

namespace plantar::contact {

class BumpTerrain final : public Terrain {
public:
  /// @p amplitude A (m, finite), @p wavelength_x L_x and @p wavelength_y L_y (m, > 0 or 0 for
  /// infinite), @p level z0 (m, finite). Throws std::invalid_argument naming the argument.
  BumpTerrain(double amplitude, double wavelength_x, double wavelength_y, double level);
  double height(double x, double y) const override;
  Eigen::Vector2d gradient(double x, double y) const override;

private:
  double amplitude_, level_;
  double wave_x_, wave_y_; // 2 pi / L, 0 for L = 0
};

} // namespace plantar::contact
