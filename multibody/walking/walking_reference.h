// Whole-body joint reference trajectories: the walk (ZMP preview control + leg IK), standing
// still, and the lean test of David et al. 2008.
#pragma once

#include "multibody/model.h"
#include "multibody/walking/footstep_plan.h"
#include "multibody/walking/humanoid.h"
#include "multibody/walking/joint_reference.h"
#include "multibody/walking/leg_solver.h"
#include "multibody/walking/preview_control.h"

#include <Eigen/Core>
#include <Eigen/Geometry>

namespace plantar::walking {

/// The standing posture's numbers (the joint angles are the Humanoid's posture).
struct PostureParameters {
  /// CoM height above the sole frames in the standing posture [m], > 0; it sets the constant
  /// waist height (bent knees). Default: jrl-walkgen's HRP-2 value.
  double com_height = 0.814;
  /// Fixed-point iterations placing the waist under a CoM target, and their tolerance [m].
  int max_com_iterations = 50;
  double com_tolerance = 1e-10;
  /// How the legs are solved (closed form where it fits, or always numerical).
  LegIkMethod leg_ik = LegIkMethod::automatic;
};

/// The walk: footstep plan, CoM from preview control, and the joint reference.
struct WalkingPattern {
  FootstepPlan plan;
  PreviewGains gains;
  Eigen::MatrixX3d com_x, com_y;   ///< n x 3 cart-table states (position, velocity, acceleration)
  Eigen::MatrixX2d cart_table_zmp; ///< n x 2, p = c - z_c/g c'' of the CoM trajectory [m]
  JointReference reference;
};

/// Generates the walk: ZMP reference from the footstep plan -> CoM (x, y) by preview control
/// (preview.com_height is overwritten with posture.com_height + walk.ground_clearance) -> waist
/// placed so that the whole-body CoM of the URDF model equals the CoM reference (fixed-point
/// iteration), waist height constant above the mean planned ground height of the two soles
/// (constant on flat ground), waist yaw the mean of the sole yaws -> legs by the
/// leg inverse kinematics (LegSolver). @p model: the robot without compliant ankles, free base;
/// @p humanoid resolved on it.
/// @throws std::runtime_error if a leg pose is out of reach or outside its joint limits (naming
/// the joint, the time and the value), or if the CoM iteration does not converge.
WalkingPattern make_walking_pattern(const multibody::Model& model, const Humanoid& humanoid,
                                    const WalkingParameters& walk,
                                    PreviewControlParameters preview = {},
                                    const PostureParameters& posture = {});

/// Standing still with bent knees, CoM above the centre of the feet (sole centres at
/// right_sole, left_sole), for `duration` seconds.
JointReference make_standing_reference(const multibody::Model& model, const Humanoid& humanoid,
                                       double duration, const Footstep& right_sole,
                                       const Footstep& left_sole,
                                       const PostureParameters& posture = {},
                                       double period = 0.005);

/// The lean test: feet fixed (at right_sole, left_sole), waist origin fixed at its standing
/// position, waist roll
/// (rotation about the world x axis, positive = left hip up) commanded gradually:
///   phi(t) = final_angle * s((t - start_time) / ramp_time),  s = quintic_transition,
/// then held until start_time + ramp_time + hold_time. The legs follow by IK.
struct LeanParameters {
  double final_angle = 14.3 * M_PI / 180.0; ///< [rad], |.| <= 0.35 (paper: 14.3 deg)
  double start_time = 0.5;                  ///< standing before the ramp [s], >= 0
  double ramp_time = 3.0;                   ///< [s], > 0
  double hold_time = 2.0;                   ///< [s], >= 0
  double period = 0.005;                    ///< [s], (0, 0.1]
};
JointReference make_lean_reference(const multibody::Model& model, const Humanoid& humanoid,
                                   const LeanParameters& lean, const Footstep& right_sole,
                                   const Footstep& left_sole,
                                   const PostureParameters& posture = {});

} // namespace plantar::walking
