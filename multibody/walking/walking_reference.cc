#include "multibody/walking/walking_reference.h"

#include "multibody/walking/leg_ik.h"

#include <algorithm>
#include <cmath>
#include <sstream>
#include <stdexcept>

namespace plantar::walking {
namespace {

Eigen::Isometry3d sole_pose(const Eigen::Vector3d& position, double yaw) {
  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
  pose.translation() = position;
  pose.linear() = Eigen::AngleAxisd(yaw, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  return pose;
}

/// Whole-body posture solver shared by the three references.
class PostureSolver {
public:
  PostureSolver(const urdf::ModelInterface& model, const UpperBodyPosture& posture)
      : mass_model_(make_mass_model(model)), mass_data_(mass_model_),
        right_(read_leg_geometry(model, LegSide::right)),
        left_(read_leg_geometry(model, LegSide::left)), posture_(posture) {
    if (!(posture.com_height > 0.5 && posture.com_height < 0.9))
      throw std::invalid_argument("UpperBodyPosture.com_height = " +
                                  std::to_string(posture.com_height) + " m is outside (0.5, 0.9)");
    if (posture.max_com_iterations <= 0 || !(posture.com_tolerance > 0.0))
      throw std::invalid_argument("UpperBodyPosture: max_com_iterations must be > 0 and "
                                  "com_tolerance > 0");
  }

  /// Leg IK for a base pose and two sole poses; fills q (legs) and returns the CoM.
  Eigen::Vector3d legs(const Eigen::Isometry3d& base, const Eigen::Isometry3d& right_sole,
                       const Eigen::Isometry3d& left_sole, double time, RobotAngles& q) {
    q = posture_.angles;
    LegAngles leg_q;
    try {
      solve_leg_ik(right_, base, right_sole, leg_q);
      check_limits(right_, leg_q, time);
      q.segment<6>(right_leg_start) = leg_q;
      solve_leg_ik(left_, base, left_sole, leg_q);
      check_limits(left_, leg_q, time);
      q.segment<6>(left_leg_start) = leg_q;
    } catch (const std::runtime_error& error) {
      std::ostringstream msg;
      msg << "joint reference at t = " << time << " s: " << error.what();
      throw std::runtime_error(msg.str());
    }
    return centre_of_mass(mass_model_, mass_data_, base, q);
  }

  /// Moves the base horizontally (and vertically if `fix_height` is false) until the CoM equals
  /// `com_target` in the components that are solved for.
  Eigen::Vector3d place_base(Eigen::Isometry3d& base, const Eigen::Vector3d& com_target,
                             bool solve_height, const Eigen::Isometry3d& right_sole,
                             const Eigen::Isometry3d& left_sole, double time, RobotAngles& q) {
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

  /// Standing base pose: base over the feet centre, height such that CoM z = com_height.
  Eigen::Isometry3d standing_base(const Footstep& right, const Footstep& left, RobotAngles& q,
                                  Eigen::Vector3d& com) {
    Eigen::Isometry3d base = Eigen::Isometry3d::Identity();
    const double yaw = right.yaw + 0.5 * std::remainder(left.yaw - right.yaw, 2.0 * M_PI);
    base.linear() = Eigen::AngleAxisd(yaw, Eigen::Vector3d::UnitZ()).toRotationMatrix();
    base.translation() = Eigen::Vector3d(0.5 * (right.x + left.x), 0.5 * (right.y + left.y),
                                         posture_.com_height - 0.16);
    const Eigen::Vector3d target(base.translation().x(), base.translation().y(),
                                 posture_.com_height);
    com = place_base(base, target, true, sole_pose({right.x, right.y, 0.0}, right.yaw),
                     sole_pose({left.x, left.y, 0.0}, left.yaw), 0.0, q);
    return base;
  }

private:
  void check_limits(const LegGeometry& leg, const LegAngles& q, double time) const {
    for (int i = 0; i < 6; ++i)
      if (q(i) < leg.lower_limit(i) || q(i) > leg.upper_limit(i)) {
        std::ostringstream msg;
        msg << "joint reference: " << leg.joint_names[i] << " = " << q(i) << " rad at t = " << time
            << " s is outside its limits [" << leg.lower_limit(i) << ", " << leg.upper_limit(i)
            << "]";
        throw std::runtime_error(msg.str());
      }
  }

  MassModel mass_model_;
  MassModelData mass_data_;
  LegGeometry right_, left_;
  UpperBodyPosture posture_;
};

} // namespace

RobotAngles half_sitting_upper_body() {
  const double deg = M_PI / 180.0;
  RobotAngles q = RobotAngles::Zero();
  const double arm[7] = {15, -10, 0, -30, 0, 0, 10};
  for (int i = 0; i < 7; ++i) {
    q(right_arm_start + i) = arm[i] * deg;
    q(left_arm_start + i) = (i == 1 ? -arm[i] : arm[i]) * deg;
  }
  return q;
}

WalkingPattern make_walking_pattern(const urdf::ModelInterface& model,
                                    const WalkingParameters& walk, PreviewControlParameters preview,
                                    const UpperBodyPosture& posture) {
  WalkingPattern pattern;
  pattern.plan = make_footstep_plan(walk);
  preview.period = walk.period;
  preview.com_height = posture.com_height + walk.ground_clearance;
  pattern.gains = compute_preview_gains(preview);
  PostureSolver solver(model, posture);
  RobotAngles q;
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
  ref.resize(n, walk.period);
  Eigen::Isometry3d base = base0;
  for (int k = 0; k < n; ++k) {
    const double time = plan.time(k);
    const double yaw =
        plan.right_yaw(k) + 0.5 * std::remainder(plan.left_yaw(k) - plan.right_yaw(k), 2.0 * M_PI);
    base.linear() = Eigen::AngleAxisd(yaw, Eigen::Vector3d::UnitZ()).toRotationMatrix();
    const Eigen::Vector3d target(pattern.com_x(k, 0), pattern.com_y(k, 0), 0.0);
    const Eigen::Isometry3d right =
        sole_pose(plan.right_sole.row(k).transpose(), plan.right_yaw(k));
    const Eigen::Isometry3d left = sole_pose(plan.left_sole.row(k).transpose(), plan.left_yaw(k));
    const Eigen::Vector3d com = solver.place_base(base, target, false, right, left, time, q);
    ref.set(k, base, q, com);
  }
  return pattern;
}

JointReference make_standing_reference(const urdf::ModelInterface& model, double duration,
                                       const Footstep& right_sole, const Footstep& left_sole,
                                       const UpperBodyPosture& posture, double period) {
  if (!(duration >= 0.0) || !(period > 0.0 && period <= 0.1))
    throw std::invalid_argument("make_standing_reference: duration = " + std::to_string(duration) +
                                " s must be >= 0 and period = " + std::to_string(period) +
                                " s in (0, 0.1]");
  PostureSolver solver(model, posture);
  RobotAngles q;
  Eigen::Vector3d com;
  const Eigen::Isometry3d base = solver.standing_base(right_sole, left_sole, q, com);
  const int n = static_cast<int>(std::floor(duration / period + 1e-9)) + 1;
  JointReference ref;
  ref.resize(n, period);
  for (int k = 0; k < n; ++k)
    ref.set(k, base, q, com);
  return ref;
}

JointReference make_lean_reference(const urdf::ModelInterface& model, const LeanParameters& lean,
                                   const UpperBodyPosture& posture) {
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
  PostureSolver solver(model, posture);
  const Footstep right{0.0, -0.105, 0.0}, left{0.0, 0.105, 0.0};
  RobotAngles q;
  Eigen::Vector3d com;
  const Eigen::Isometry3d base0 = solver.standing_base(right, left, q, com);
  const double duration = lean.start_time + lean.ramp_time + lean.hold_time;
  const int n = static_cast<int>(std::floor(duration / lean.period + 1e-9)) + 1;
  JointReference ref;
  ref.resize(n, lean.period);
  const Eigen::Isometry3d right_pose = sole_pose({right.x, right.y, 0.0}, 0.0);
  const Eigen::Isometry3d left_pose = sole_pose({left.x, left.y, 0.0}, 0.0);
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
