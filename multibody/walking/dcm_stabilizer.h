#pragma once
// A linear-inverted-pendulum balance stabilizer (Kajita et al. 2010, IROS; Caron et al. 2019,
// ICRA): DCM feedback to a desired ZMP, its distribution between the feet, and foot
// admittance that only changes where the feet are asked to be (the caller turns the foot
// offsets into joint references).
//   DCM error          e = xi - xi_ref  (horizontal, m);  E' = e - E / T_i  (leaky integral)
//   desired ZMP        p_d = p_ref + (1 + k_p / omega) e + k_i E
//                      (with xi' = omega (xi - p) and p = p_d: e' = -k_p e - omega k_i E)
//   distribution       one foot in contact: its CoP target p_d, force f; both: p_d projected
//                      on the segment between the sole centres, p_s = p_R + s (p_L - p_R),
//                      s in [0, 1], CoP targets p_i + (p_d - p_s), forces f_L = s f,
//                      f_R = (1 - s) f (f: the measured total)
//   ZMP deficit        d = p_d - its clamped CoP target (world) with one foot in contact; else 0
//   foot damping       per foot in contact, sole axes, CoP targets clamped to the sole (its
//                      support polygon shrunk by a margin when the plan gives one):
//                      roll'  = (cop_y - cop_y,d) f_z / D_roll - roll / T_c
//                      pitch' = (cop_x,d - cop_x) f_z / D_pitch - pitch / T_c
//                      (a foot out of contact: only the decay)
//   force difference   z' = ((f_L,d - f_R,d) - (f_L - f_R)) / D_z - z / T_z  (both feet down;
//                      else the decay); left sole lowered by z / 2, right raised by z / 2.
// Explicit Euler at the control period dt. No heap allocation.

#include <Eigen/Core>

#include <array>

namespace plantar::walking {

struct DcmStabilizerParameters {
  // Structure: Kajita et al. 2010 and Caron et al. 2019; the values are tuned on the HRP-2
  // model of this repository (docs/stabilizer.md: what each was tried at).
  double omega = 3.47;                ///< sqrt(g / z_c), 1/s, > 0 (set from the reference)
  double dcm_gain = 10;               ///< k_p, 1/s, >= 0
  double dcm_integral_gain = 0;       ///< k_i, 1/s, >= 0
  double integral_time_constant = 10; ///< T_i, s, > 0 (mc_rtc's HRP-4 value)
  double foot_damping = 2000;         ///< D, N m s/rad, > 0
  /// D of the roll and the pitch axis (N m s/rad); an entry <= 0 takes foot_damping.
  Eigen::Vector2d tilt_damping = Eigen::Vector2d::Zero();
  double foot_time_constant = 1;             ///< T_c, s, > 0
  double force_damping = 1e5;                ///< D_z, N s/m, > 0 (mc_rtc's 1/1e-4 chatters here)
  double force_time_constant = 1;            ///< T_z, s, > 0
  double max_foot_rotation = 0.1;            ///< rad: |roll|, |pitch| clamp
  double max_leg_offset = 0.03;              ///< m: |z| clamp
  Eigen::Vector2d sole_half_size{0.1, 0.06}; ///< m: CoP targets kept inside +-this (sole axes)
  double support_margin = 0.01;  ///< m, >= 0: CoP targets kept this far inside a support polygon
  double min_contact_force = 20; ///< N: a lighter foot has no CoP
};

/// One foot as the stabilizer sees it.
struct StabilizerFoot {
  Eigen::Vector3d position = Eigen::Vector3d::Zero();     ///< reference sole centre, world, m
  Eigen::Matrix3d rotation = Eigen::Matrix3d::Identity(); ///< reference sole axes -> world
  bool contact = false;                                   ///< planned on the ground and loaded
  Eigen::Vector3d force = Eigen::Vector3d::Zero();        ///< measured, sole axes, N
  Eigen::Vector3d moment = Eigen::Vector3d::Zero(); ///< measured about the sole centre, sole axes
  /// The planned support polygon, (x, y) in sole axes [m], counter-clockwise (2 x m, m >= 3);
  /// nullptr: the rectangle +-sole_half_size.
  const Eigen::Matrix2Xd* support = nullptr;
};

/// What the feet should do: offsets of the sole relative to its reference.
struct FootOffset {
  double roll = 0, pitch = 0; ///< rad, about the sole's x and y axes
  double height = 0;          ///< m, along world z
};

class DcmStabilizer {
public:
  explicit DcmStabilizer(const DcmStabilizerParameters& parameters);
  const DcmStabilizerParameters& parameters() const { return parameters_; }
  /// One control period. @param dcm, dcm_ref the estimated and reference DCM (x, y; m);
  /// @param zmp_ref the reference ZMP (m); @param feet right, left; @param dt s.
  void update(const Eigen::Vector2d& dcm, const Eigen::Vector2d& dcm_ref,
              const Eigen::Vector2d& zmp_ref, const std::array<StabilizerFoot, 2>& feet, double dt);
  const std::array<FootOffset, 2>& offsets() const { return offsets_; }
  const Eigen::Vector2d& desired_zmp() const { return desired_zmp_; }
  const Eigen::Vector2d& dcm_error() const { return error_; }
  /// What the one loaded sole cannot take of the desired ZMP (world x, y; m).
  const Eigen::Vector2d& zmp_deficit() const { return zmp_deficit_; }
  /// @p cop (world x, y; m) minus the nearest CoP target @p foot can take (its support polygon
  /// shrunk by support_margin, or +-sole_half_size) shrunk by a further @p margin (m, >= 0),
  /// world x, y [m]; 0 inside.
  Eigen::Vector2d cop_excess(const StabilizerFoot& foot, const Eigen::Vector2d& cop,
                             double margin = 0) const;

private:
  /// The CoP target nearest @p cop that @p f can take (sole axes, m) and the excess (world).
  Eigen::Vector2d clamped_target(const StabilizerFoot& f, const Eigen::Vector2d& cop, double margin,
                                 Eigen::Vector2d& target) const;
  DcmStabilizerParameters parameters_;
  std::array<FootOffset, 2> offsets_{};
  double force_offset_ = 0; ///< z
  Eigen::Vector2d error_ = Eigen::Vector2d::Zero(), integral_ = Eigen::Vector2d::Zero();
  Eigen::Vector2d desired_zmp_ = Eigen::Vector2d::Zero();
  Eigen::Vector2d zmp_deficit_ = Eigen::Vector2d::Zero();
};

} // namespace plantar::walking
