// Footstep plan: timing, ZMP reference and swing-foot trajectories of a walk.
#pragma once

#include <Eigen/Core>
#include <vector>

namespace plantar::walking {

/// A foot placement: centre of the sole's bottom face (r_sole / l_sole frame). On flat ground
/// z, roll and pitch are 0; on a terrain (terrain_footsteps.h) the sole rests on the plane
/// they give. The sole's orientation is R = R_z(yaw) R_y(pitch) R_x(roll).
struct Footstep {
  double x = 0.0;     ///< [m]
  double y = 0.0;     ///< [m]
  double yaw = 0.0;   ///< [rad], (-pi, pi]
  double z = 0.0;     ///< height of the sole centre [m]
  double roll = 0.0;  ///< about the sole's x axis [rad], |.| < pi/2
  double pitch = 0.0; ///< about the yawed y axis [rad], |.| < pi/2
  /// Where the ZMP reference rests on this sole in single support: (x, y) in the sole frame
  /// [m]; the sole centre unless the placement moves it inside its support.
  double zmp_x = 0.0, zmp_y = 0.0;
  /// The sole's support polygon: (x, y) in the sole frame [m], counter-clockwise (2 x m);
  /// empty: the whole sole.
  Eigen::Matrix2Xd support{};
  /// The swing onto this footstep moves only vertically over this fraction of the single
  /// support at each end, [0, 0.45]: its horizontal motion (and tilt, yaw) follows
  /// quintic_transition((tau - f) / (1 - 2 f)), so that it crosses the ground between the two
  /// placements above it (swing_lift_fraction, terrain_footsteps.h); 0 on flat ground.
  double lift_fraction = 0.0;
};

/// The horizontal world position of a footstep's ZMP target [m]:
/// (x, y) + [R (zmp_x, zmp_y, 0)]_xy with R = footstep_rotation(yaw, pitch, roll).
Eigen::Vector2d zmp_target(const Footstep& f);

/// The sole's orientation R_z(yaw) R_y(pitch) R_x(roll) (world <- sole).
Eigen::Matrix3d footstep_rotation(double yaw, double pitch, double roll);

/// The walk. Defaults: the paper's walk (David et al. 2008, sec. IV): six steps in six seconds,
/// peak forward speed of the reference point (the waist) about 0.3 m/s, steps no longer than
/// 0.45 m (max_step_length). Both paper figures cannot be met together with HRP-2's 0.8 s step
/// cycle: a 0.45 m step pushes the waist to about 0.5 m/s. The default plan keeps 0.3 m/s
/// (strides of 0.27 m, 0.135 m advance per step) and enforces 0.45 m as the upper bound; see
/// docs/walking.md.
/// Timing of the 6 s walk: initial double support 0.6 s (ZMP from the feet centre to the first
/// support foot) + 6 single supports of 0.78 s with 5 double supports of 0.02 s between them
/// (HRP-2's timings) + final double support 0.62 s (ZMP back to the feet centre) = 6.0 s;
/// standing phases before and after (standing_before, standing_after) are added around it.
struct WalkingParameters {
  double period = 0.005;                    ///< pattern period T [s], (0, 0.1]
  double single_support_time = 0.78;        ///< [s], >= 2 period
  double double_support_time = 0.02;        ///< [s], >= period
  double initial_double_support_time = 0.6; ///< [s], >= period
  double final_double_support_time = 0.62;  ///< [s], >= period
  double standing_before = 1.0;             ///< standing still before the walk [s], >= 0
  double standing_after = 1.0;              ///< standing still after the walk [s], >= 0
  double step_height = 0.07;                ///< swing-foot apex above the ground [m], [0, 0.3]
  double max_step_length = 0.45;            ///< longest allowed swing-foot travel [m], > 0
  bool right_foot_first = true;             ///< the right foot swings first
  /// Planned vertical speed of the swing sole at touchdown [m/s], [0, 1]; 0: it lands at rest
  /// (the paper's walk). With v > 0, v * single_support_time <= 19 step_height keeps the
  /// apex at step_height (swing_foot_height).
  double touchdown_velocity = 0.0;
  /// Height of the sole frames above the ground [m], [0, 0.1]: a sole of that thickness under
  /// the feet. The cart-table height becomes com_height + ground_clearance (the CoM height
  /// above the ground, where the ZMP is).
  double ground_clearance = 0.0;
  /// On a terrain (terrain_footsteps.h): the swing sole stays this far above the ground between
  /// its placements (or as high as its planned height above its planned ground, if lower)
  /// [m], [0, 0.05].
  double swing_ground_margin = 0.01;
  /// The least Footstep::lift_fraction of every swing, [0, 0.45]: a swing over a ground the
  /// plan does not know lifts before it moves (0: the paper's swing).
  double min_lift_fraction = 0.0;
  Footstep initial_right{0.0, -0.105, 0.0}; ///< right sole at the start
  Footstep initial_left{0.0, 0.105, 0.0}; ///< left sole at the start (straight-walk tests: +-0.105)
  /// Landing placements of the successive swing feet (alternating, first = right if
  /// right_foot_first). Default: 6 steps, swing travel 0.135, 0.27, 0.27, 0.27, 0.27, 0.135 m,
  /// ending with the feet side by side 0.675 m ahead.
  std::vector<Footstep> footsteps = {{0.135, -0.105, 0.0}, {0.27, 0.105, 0.0},
                                     {0.405, -0.105, 0.0}, {0.54, 0.105, 0.0},
                                     {0.675, -0.105, 0.0}, {0.675, 0.105, 0.0}};
};

/// Throws std::invalid_argument naming the parameter, its value and the allowed range.
void check_walking_parameters(const WalkingParameters& params);

/// Phase of the walk at one sample.
enum class SupportPhase { double_support, right_support, left_support };

/// The plan sampled at the pattern period (all arrays have n_samples rows).
struct FootstepPlan {
  int n_samples = 0;
  Eigen::VectorXd time;           ///< t_k = k T [s]
  Eigen::MatrixX2d zmp_reference; ///< p_ref(t) [m]: the support sole's ZMP target (zmp_target)
                                  ///< in single support, linear between the two in double support
  Eigen::MatrixX3d right_sole;    ///< (x, y, z) of r_sole [m]
  Eigen::MatrixX3d left_sole;     ///< (x, y, z) of l_sole [m]
  Eigen::VectorXd right_yaw, left_yaw;    ///< [rad]
  Eigen::MatrixX2d right_tilt, left_tilt; ///< (roll, pitch) of each sole [rad]
  /// Planned ground height under each sole (right, left) [m]: the placement's z while the foot
  /// is down; during a swing z_from + (z_to - z_from) s(tau) (the line the swing rides on).
  Eigen::MatrixX2d ground;
  /// The placements' support polygons (Footstep::support): 0 the initial right sole, 1 the
  /// initial left, 2 + i footsteps[i].
  std::vector<Eigen::Matrix2Xd> supports;
  /// Per sample, the placement (index into supports) each sole (right, left) rests on or
  /// swings to.
  Eigen::MatrixX2i support_index;
  std::vector<SupportPhase> phase;
  /// Per sample, each sole's (right, left) swing: the horizontal progress s in [0, 1]
  /// (SwingSample::progress) and the planned touchdown time [s]; both -1 while it is down.
  Eigen::MatrixX2d swing_progress, swing_end;
  double walk_start = 0.0, walk_end = 0.0; ///< start and end of the walk proper [s]
};

/// Minimum-jerk (quintic) transition s(tau) = 10 tau^3 - 15 tau^4 + 6 tau^5 on tau in [0, 1],
/// s(0) = 0, s(1) = 1, zero velocity and acceleration at both ends. Returns (s, ds/dtau,
/// d2s/dtau2).
Eigen::Vector3d quintic_transition(double tau);

/// Swing height profile h(tau) = 64 tau^3 (1 - tau)^3 (apex 1 at tau = 1/2; zero value,
/// velocity and acceleration at lift-off and touchdown). Returns (h, dh/dtau, d2h/dtau2).
Eigen::Vector3d swing_height_profile(double tau);

/// Touchdown term g(tau) = tau^3 (1 - tau) (2 tau - 1)^2: g = g' = g'' = 0 at tau = 0,
/// g(1/2) = g'(1/2) = 0, g(1) = 0, g'(1) = -1 (g''(1) = -14), g >= 0 on [0, 1]. Returns (g,
/// dg/dtau, d2g/dtau2).
Eigen::Vector3d touchdown_profile(double tau);

/// Height of the swing sole above the ground, tau = (t - t_lift-off) / T_ss in [0, 1]:
///   z(tau) = H h(tau) + v T_ss g(tau)
/// (H = step_height [m], v = touchdown_velocity [m/s], T_ss = single_support_time [s]; h =
/// swing_height_profile, g = touchdown_profile). z, dz/dt and d2z/dt2 are 0 at lift-off;
/// z(1/2) = H with dz/dt = 0; z(1) = 0 with dz/dt = -v. The apex is H (at tau = 1/2) for
/// v T_ss <= 19.2 H (checked with 19: check_walking_parameters); v = 0 gives H h(tau) exactly.
/// Returns (z [m], dz/dt [m/s], d2z/dt2 [m/s^2]).
Eigen::Vector3d swing_foot_height(const WalkingParameters& params, double tau);

/// The swing sole from @p from onto @p to at tau in [0, 1] of the single support: x, y, yaw,
/// roll, pitch and the planned ground g = from.z + s (to.z - from.z) by
/// s = quintic_transition((tau - f) / (1 - 2 f)), f = max(to.lift_fraction,
/// p.min_lift_fraction); the sole's height z = g + swing_foot_height(tau).
struct SwingSample {
  Footstep sole;         ///< pose (x, y, z, yaw, roll, pitch); the rest default
  double ground = 0.0;   ///< g, m
  double progress = 0.0; ///< s in [0, 1]: 0 on the lift-off placement, 1 on the landing one
};
SwingSample swing_sample(const WalkingParameters& p, const Footstep& from, const Footstep& to,
                         double tau);

/// Samples the plan: ZMP reference and both sole trajectories. The swing sole moves
/// horizontally (and in yaw, roll, pitch and the placements' height difference) by
/// quintic_transition s(tau) and vertically, in addition, by swing_foot_height over the
/// single-support time: z(tau) = z_from + (z_to - z_from) s(tau) + swing_foot_height(tau). From the
/// planned touchdown on, the sole's reference stays at z = 0: the ground decides the real
/// touchdown; a foot still in the air (a late touchdown) is driven down only by the joint PD
/// tracking that reference. (z = 0 is the placement's height.)
FootstepPlan make_footstep_plan(const WalkingParameters& params);

} // namespace plantar::walking
