#include "multibody/walking/walking_reference.h"

#include "multibody/center_of_mass.h"
#include "multibody/data.h"
#include "multibody/kinematics.h"
#include "multibody/walking/leg_solver.h"

#include <algorithm>
#include <cmath>
#include <sstream>
#include <stdexcept>

namespace plantar::walking {
namespace {

Eigen::Isometry3d sole_pose(const Eigen::Vector3d& position, double yaw, double roll = 0.0,
                            double pitch = 0.0) {
  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
  pose.translation() = position;
  pose.linear() = footstep_rotation(yaw, pitch, roll);
  return pose;
}

Eigen::Isometry3d sole_pose(const Footstep& f) {
  return sole_pose({f.x, f.y, f.z}, f.yaw, f.roll, f.pitch);
}

/// Whole-body posture solver shared by the three references.
class PostureSolver {
public:
  PostureSolver(const multibody::Model& model, const Humanoid& humanoid,
                const PostureParameters& posture)
      : model_(model), humanoid_(humanoid), posture_(posture), data_(model),
        q_model_(model.neutral_configuration()), legs_{LegSolver(model, humanoid, LegSide::right,
                                                                 posture.leg_ik),
                                                       LegSolver(model, humanoid, LegSide::left,
                                                                 posture.leg_ik)} {
    if (!model.has_free_base() || humanoid.base_body != 1)
      throw std::invalid_argument("walking reference: the model needs a free-floating base at "
                                  "the base link");
    if (!(posture.com_height > 0.0))
      throw std::invalid_argument("PostureParameters.com_height = " +
                                  std::to_string(posture.com_height) + " m must be > 0");
    if (posture.max_com_iterations <= 0 || !(posture.com_tolerance > 0.0))
      throw std::invalid_argument("PostureParameters: max_com_iterations must be > 0 and "
                                  "com_tolerance > 0");
    // Warm start of the numerical leg IK: the posture's leg angles.
    for (int side = 0; side < 2; ++side)
      for (int k = 0; k < 6; ++k)
        leg_q_[side][k] = humanoid.posture[humanoid.leg_columns[side][k]];
  }

  /// Leg IK for a base pose and two sole poses; fills q (controlled joints) and returns the CoM.
  Eigen::Vector3d legs(const Eigen::Isometry3d& base, const Eigen::Isometry3d& right_sole,
                       const Eigen::Isometry3d& left_sole, double time, Eigen::VectorXd& q) {
    q = humanoid_.posture;
    try {
      const Eigen::Isometry3d* soles[2] = {&right_sole, &left_sole};
      for (int side = 0; side < 2; ++side) {
        legs_[side].solve(base, *soles[side], leg_q_[side]);
        for (int k = 0; k < 6; ++k)
          q[humanoid_.leg_columns[side][k]] = leg_q_[side][k];
      }
    } catch (const std::runtime_error& error) {
      std::ostringstream msg;
      msg << "joint reference at t = " << time << " s: " << error.what();
      throw std::runtime_error(msg.str());
    }
    return centre_of_mass(base, q);
  }

  /// Whole-body CoM (world) for the base pose and the controlled joints @p q.
  Eigen::Vector3d centre_of_mass(const Eigen::Isometry3d& base, const Eigen::VectorXd& q) {
    q_model_.head<3>() = base.translation();
    const Eigen::Quaterniond rotation(base.linear());
    q_model_.segment<4>(3) << rotation.x(), rotation.y(), rotation.z(), rotation.w();
    humanoid_.to_configuration(model_, q, q_model_);
    multibody::forward_kinematics(model_, data_, q_model_);
    return multibody::center_of_mass(model_, data_);
  }

  /// Moves the base horizontally (and vertically if `solve_height`) until the CoM equals
  /// `com_target` in the components that are solved for.
  Eigen::Vector3d place_base(Eigen::Isometry3d& base, const Eigen::Vector3d& com_target,
                             bool solve_height, const Eigen::Isometry3d& right_sole,
                             const Eigen::Isometry3d& left_sole, double time, Eigen::VectorXd& q) {
    Eigen::Vector3d com;
    for (int iteration = 0; iteration < posture_.max_com_iterations; ++iteration) {
      com = legs(base, right_sole, left_sole, time, q);
      Eigen::Vector3d error = com_target - com;
      if (!solve_height)
        error.z() = 0.0;
      if (error.norm() < posture_.com_tolerance)
        return com;
      base.translation() += error;
    }
    std::ostringstream msg;
    msg << "CoM placement did not converge at t = " << time << " s in "
        << posture_.max_com_iterations << " iterations (error "
        << (com_target - com).head<2>().norm() << " m)";
    throw std::runtime_error(msg.str());
  }

  /// Standing base pose: base over the feet centre, height such that CoM z = com_height above
  /// the mean height of the two placements.
  Eigen::Isometry3d standing_base(const Footstep& right, const Footstep& left, Eigen::VectorXd& q,
                                  Eigen::Vector3d& com) {
    Eigen::Isometry3d base = Eigen::Isometry3d::Identity();
    const double yaw = right.yaw + 0.5 * std::remainder(left.yaw - right.yaw, 2.0 * M_PI);
    base.linear() = Eigen::AngleAxisd(yaw, Eigen::Vector3d::UnitZ()).toRotationMatrix();
    // First guess: the base as far above the CoM target as it is above the posture's CoM. The
    // CoM stands over the mean of the soles' ZMP targets, where the walk's ZMP reference starts
    // (the sole centres on flat ground).
    const double com_above_base = centre_of_mass(base, humanoid_.posture).z();
    const double ground = 0.5 * (right.z + left.z);
    const Eigen::Vector2d centre = 0.5 * (zmp_target(right) + zmp_target(left));
    base.translation() =
        Eigen::Vector3d(centre.x(), centre.y(), ground + posture_.com_height - com_above_base);
    const Eigen::Vector3d target(base.translation().x(), base.translation().y(),
                                 ground + posture_.com_height);
    com = place_base(base, target, true, sole_pose(right), sole_pose(left), 0.0, q);
    return base;
  }

private:
  const multibody::Model& model_;
  const Humanoid& humanoid_;
  PostureParameters posture_;
  multibody::Data data_;
  Eigen::VectorXd q_model_;
  LegSolver legs_[2];
  LegAngles leg_q_[2];
};

} // namespace

WalkingPattern make_walking_pattern(const multibody::Model& model, const Humanoid& humanoid,
                                    const WalkingParameters& walk, PreviewControlParameters preview,
                                    const PostureParameters& posture) {
  WalkingPattern pattern;
  pattern.plan = make_footstep_plan(walk);
  preview.period = walk.period;
  preview.com_height = posture.com_height + walk.ground_clearance;
  pattern.gains = compute_preview_gains(preview);
  PostureSolver solver(model, humanoid, posture);
  Eigen::VectorXd q;
  Eigen::Vector3d com0;
  const Eigen::Isometry3d base0 =
      solver.standing_base(walk.initial_right, walk.initial_left, q, com0);
  const FootstepPlan& plan = pattern.plan;
  const int n = plan.n_samples;
  Eigen::VectorXd zmp_component;
  pattern.com_x.resize(n, 3);
  pattern.com_y.resize(n, 3);
  run_preview_control(preview, pattern.gains, plan.zmp_reference.col(0),
                      Eigen::Vector3d(com0.x(), 0.0, 0.0), pattern.com_x, zmp_component);
  pattern.cart_table_zmp.resize(n, 2);
  pattern.cart_table_zmp.col(0) = zmp_component;
  run_preview_control(preview, pattern.gains, plan.zmp_reference.col(1),
                      Eigen::Vector3d(com0.y(), 0.0, 0.0), pattern.com_y, zmp_component);
  pattern.cart_table_zmp.col(1) = zmp_component;

  JointReference& ref = pattern.reference;
  ref.resize(n, walk.period, humanoid.joint_names);
  ref.ground = plan.ground;
  ref.supports = plan.supports;
  ref.support_index = plan.support_index;
  ref.swing_progress = plan.swing_progress;
  ref.swing_end = plan.swing_end;
  Eigen::Isometry3d base = base0;
  const double ground0 = plan.ground.row(0).mean();
  for (int k = 0; k < n; ++k) {
    const double time = plan.time(k);
    const double yaw =
        plan.right_yaw(k) + 0.5 * std::remainder(plan.left_yaw(k) - plan.right_yaw(k), 2.0 * M_PI);
    base.linear() = Eigen::AngleAxisd(yaw, Eigen::Vector3d::UnitZ()).toRotationMatrix();
    // The waist follows the mean planned ground height of the two soles (0 on flat ground).
    base.translation().z() = base0.translation().z() + plan.ground.row(k).mean() - ground0;
    const Eigen::Vector3d target(pattern.com_x(k, 0), pattern.com_y(k, 0), 0.0);
    const Eigen::Isometry3d right = sole_pose(plan.right_sole.row(k).transpose(), plan.right_yaw(k),
                                              plan.right_tilt(k, 0), plan.right_tilt(k, 1));
    const Eigen::Isometry3d left = sole_pose(plan.left_sole.row(k).transpose(), plan.left_yaw(k),
                                             plan.left_tilt(k, 0), plan.left_tilt(k, 1));
    const Eigen::Vector3d com = solver.place_base(base, target, false, right, left, time, q);
    ref.set(k, base, q, com);
  }
  return pattern;
}

JointReference make_standing_reference(const multibody::Model& model, const Humanoid& humanoid,
                                       double duration, const Footstep& right_sole,
                                       const Footstep& left_sole, const PostureParameters& posture,
                                       double period) {
  if (!(duration >= 0.0) || !(period > 0.0 && period <= 0.1))
    throw std::invalid_argument("make_standing_reference: duration = " + std::to_string(duration) +
                                " s must be >= 0 and period = " + std::to_string(period) +
                                " s in (0, 0.1]");
  PostureSolver solver(model, humanoid, posture);
  Eigen::VectorXd q;
  Eigen::Vector3d com;
  const Eigen::Isometry3d base = solver.standing_base(right_sole, left_sole, q, com);
  const int n = static_cast<int>(std::floor(duration / period + 1e-9)) + 1;
  JointReference ref;
  ref.resize(n, period, humanoid.joint_names);
  for (int k = 0; k < n; ++k)
    ref.set(k, base, q, com);
  return ref;
}

JointReference make_lean_reference(const multibody::Model& model, const Humanoid& humanoid,
                                   const LeanParameters& lean, const Footstep& right,
                                   const Footstep& left, const PostureParameters& posture) {
  if (!(std::abs(lean.final_angle) <= 0.35) || !(lean.start_time >= 0.0) ||
      !(lean.ramp_time > 0.0) || !(lean.hold_time >= 0.0) ||
      !(lean.period > 0.0 && lean.period <= 0.1)) {
    std::ostringstream msg;
    msg << "LeanParameters out of range: final_angle = " << lean.final_angle
        << " rad (|.| <= 0.35), start_time = " << lean.start_time
        << " s (>= 0), ramp_time = " << lean.ramp_time << " s (> 0), hold_time = " << lean.hold_time
        << " s (>= 0), period = " << lean.period << " s ((0, 0.1])";
    throw std::invalid_argument(msg.str());
  }
  PostureSolver solver(model, humanoid, posture);
  Eigen::VectorXd q;
  Eigen::Vector3d com;
  const Eigen::Isometry3d base0 = solver.standing_base(right, left, q, com);
  const double duration = lean.start_time + lean.ramp_time + lean.hold_time;
  const int n = static_cast<int>(std::floor(duration / lean.period + 1e-9)) + 1;
  JointReference ref;
  ref.resize(n, lean.period, humanoid.joint_names);
  const Eigen::Isometry3d right_pose = sole_pose({right.x, right.y, 0.0}, right.yaw);
  const Eigen::Isometry3d left_pose = sole_pose({left.x, left.y, 0.0}, left.yaw);
  for (int k = 0; k < n; ++k) {
    const double time = k * lean.period;
    const double angle =
        lean.final_angle * quintic_transition((time - lean.start_time) / lean.ramp_time)(0);
    Eigen::Isometry3d base = base0;
    base.linear() = Eigen::AngleAxisd(angle, Eigen::Vector3d::UnitX()).toRotationMatrix();
    com = solver.legs(base, right_pose, left_pose, time, q);
    ref.set(k, base, q, com);
  }
  return ref;
}

} // namespace plantar::walking
