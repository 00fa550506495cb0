#pragma once
// A random rough surface: a Gaussian-correlated field of RMS height sigma and correlation length
// l, reproducible from a seed, by a sum of N random Fourier modes (spectral method, Shinozuka):
//   h(x) = z0 + sigma sqrt(2/N) sum_j cos(k_j . x + phi_j),
//   k_j ~ normal(0, (2 / l^2) I_2), phi_j ~ uniform[0, 2 pi), from std::mt19937_64(seed) and a
//   Box-Muller transform written here (the same numbers on every platform),
// whose covariance over realisations is sigma^2 exp(-|r|^2 / l^2) (Gaussian spectrum
// S(k) = sigma^2 l^2 / (4 pi) exp(-|k|^2 l^2 / 4)): l is the lag at which the correlation falls
// to 1/e. One realisation's spatial mean of h^2 over a large area is sigma^2 (N distinct modes);
// its autocorrelation is (1/N) sum_j cos(k_j . r), within about 1/sqrt(2 N) of exp(-r^2/l^2).
// Evaluated through a grid: h, h_x, h_y and h_xy of the mode sum at the nodes of a square grid of
// spacing l/8 over [c_x - L_x/2, c_x + L_x/2] x [c_y - L_y/2, c_y + L_y/2], interpolated bicubic
// Hermite (C1, exact at the nodes, error O((spacing/l)^4) relative to sigma). Outside the grid
// the point is clamped onto its border (height continued, gradient zero).

#include "contact/terrain.h"

#include <cstdint>
#include <vector>

namespace plantar::contact {

struct RoughTerrainParameters {
  double rms = 0.005;                ///< sigma, m, [0, 1]
  double correlation_length = 0.1;   ///< l, m, (0, 100]
  std::uint64_t seed = 1;            ///< seed of std::mt19937_64
  int modes = 256;                   ///< N, [1, 100000]
  double size_x = 4.0, size_y = 4.0; ///< L_x, L_y, m, (0, 1000]; at most 4e6 grid nodes
  double centre_x = 0.0, centre_y = 0.0, level = 0.0; ///< c_x, c_y, z0, m, finite
  /// Throws std::invalid_argument naming the field, value and range.
  void validate() const;
};

class RoughTerrain final : public Terrain {
public:
  /// Samples the mode sum on the grid (O(grid nodes x N)). Throws as
  /// RoughTerrainParameters::validate.
  explicit RoughTerrain(const RoughTerrainParameters& parameters);
  double height(double x, double y) const override;
  Eigen::Vector2d gradient(double x, double y) const override;
  /// The mode sum itself (no grid), m: the reference of the interpolation.
  double mode_height(double x, double y) const;
  double spacing() const { return spacing_; }

private:
  /// Cell (i, j) and local coordinates (u, v) in [0, 1] of the clamped point; false outside.
  bool locate(double x, double y, int& i, int& j, double& u, double& v) const;
  /// Hermite interpolation of the cell: value (derivative = 0), d/du (1) or d/dv (2).
  double interpolate(int i, int j, double u, double v, int derivative) const;

  RoughTerrainParameters parameters_;
  std::vector<Eigen::Vector2d> wave_; // k_j
  std::vector<double> phase_;         // phi_j
  double amplitude_ = 0;              // sigma sqrt(2/N)
  double spacing_ = 0, x0_ = 0, y0_ = 0;
  int nx_ = 0, ny_ = 0;
  std::vector<double> h_, hx_, hy_, hxy_; // node (i, j) at i + nx j
};

} // namespace plantar::contact
