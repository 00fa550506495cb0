#pragma once
// The LIPM walk plan of the step adjustment and step timing tests: n stances of T = 0.8 s on
// placements (0.2 k, -+0.1) m (k even: the right foot), the last one held; its reference DCM,
// the bounded solution of xi' = omega (xi - p) for the piecewise constant ZMP p = placement k:
//   xi(t) = p_k + (xi_end,k - p_k) exp(omega (t - (k + 1) T)),
//   xi_end,k = p_k+1 + (xi_end,k+1 - p_k+1) exp(-omega T),  xi_end,n-1 = p_n-1.
#include <Eigen/Core>

#include <algorithm>
#include <cmath>
#include <vector>

namespace plantar::walking::testing {

struct LipmWalkPlan {
  static constexpr int n = 10;
  static constexpr double T = 0.8; ///< s, each stance
  double omega;                    ///< 1/s
  std::vector<Eigen::Vector2d> placement, dcm_end;

  explicit LipmWalkPlan(double omega_) : omega(omega_), placement(n), dcm_end(n) {
    for (int k = 0; k < n; ++k)
      placement[k] << 0.2 * k, k % 2 == 0 ? -0.1 : 0.1;
    dcm_end[n - 1] = placement[n - 1];
    for (int k = n - 2; k >= 0; --k)
      dcm_end[k] = placement[k + 1] + (dcm_end[k + 1] - placement[k + 1]) * std::exp(-omega * T);
  }
  /// The stance k at time t (s).
  int stance_of(double t) const { return std::min(n - 1, static_cast<int>(t / T + 1e-9)); }
  /// One exact step of c'' = omega^2 (c - p) over dt (s) at constant p: CoM c (m) and its
  /// velocity cd (m/s), in place.
  void lipm_step(Eigen::Vector2d& c, Eigen::Vector2d& cd, const Eigen::Vector2d& p,
                 double dt) const {
    const double ch = std::cosh(omega * dt), sh = std::sinh(omega * dt);
    const Eigen::Vector2d x = c - p;
    c = p + x * ch + cd * sh / omega;
    cd = x * omega * sh + cd * ch;
  }
  /// The reference DCM at time t (m).
  Eigen::Vector2d dcm(double t) const {
    const int k = stance_of(t);
    if (k == n - 1)
      return placement[k];
    return placement[k] + (dcm_end[k] - placement[k]) * std::exp(omega * (t - (k + 1) * T));
  }
};

} // namespace plantar::walking::testing
