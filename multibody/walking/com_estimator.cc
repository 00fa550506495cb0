#include "multibody/walking/com_estimator.h"

#include "multibody/center_of_mass.h"
#include "multibody/jacobian.h"
#include "multibody/kinematics.h"

#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace plantar::walking {

ComEstimator::ComEstimator(const multibody::Model& model, const Humanoid& humanoid, int imu_frame,
                           const ComEstimatorParameters& parameters, double dt)
    : model_(model), parameters_(parameters), data_(model), q_(model.neutral_configuration()),
      jacobian_(6, model.nv), spring_force_(model.nv), imu_frame_(imu_frame),
      sole_frames_(humanoid.sole_frames), dt_(dt),
      filter_(dt / (parameters.velocity_time_constant + dt)) {
  if (!model.has_free_base())
    throw std::invalid_argument("ComEstimator: the model has no free base");
  if (dt <= 0 || parameters.velocity_time_constant < 0)
    throw std::invalid_argument("ComEstimator: dt > 0 and a velocity time constant >= 0 needed");
  for (int joint : humanoid.joints)
    joint_q_.push_back(model.idx_q[joint]);
  std::vector<bool> sensed(model.nq, false);
  for (int k = 0; k < 7; ++k)
    sensed[k] = true; // the base
  for (int k : joint_q_)
    sensed[k] = true;
  for (int k = 0; k < model.nq; ++k)
    if (!sensed[k])
      unsensed_q_.push_back(k);
  for (int joint = 1; joint < model.n_bodies; ++joint)
    if (model.nv_joint[joint] == 1 && !sensed[model.idx_q[joint]] &&
        model.passive_stiffness[model.idx_v[joint]] > 0) {
      spring_q_.push_back(model.idx_q[joint]);
      spring_v_.push_back(model.idx_v[joint]);
    }
  springs_.assign(spring_q_.size(), 0.0);
}

void ComEstimator::estimate_springs(const std::array<multibody::Vector6d, 2>& sole_wrenches) {
  // The last period's springs (the plan's at the first): the start of the fixed point and the
  // damper's previous state.
  if (first_springs_)
    for (std::size_t j = 0; j < spring_q_.size(); ++j)
      springs_[j] = q_[spring_q_[j]];
  for (std::size_t j = 0; j < spring_q_.size(); ++j)
    q_[spring_q_[j]] = springs_[j];
  for (int pass = 0; pass < 4; ++pass) {
    multibody::forward_kinematics(model_, data_, q_);
    spring_force_.setZero();
    for (int foot = 0; foot < 2; ++foot) {
      multibody::frame_jacobian(model_, data_, sole_frames_[foot], jacobian_);
      const Eigen::Matrix3d r =
          multibody::frame_placement(model_, data_, sole_frames_[foot]).rotation;
      multibody::Vector6d world; // [f; n about the sole origin], world axes
      world << r * sole_wrenches[foot].head<3>(), r * sole_wrenches[foot].tail<3>();
      spring_force_.noalias() += jacobian_.transpose() * world;
    }
    double change = 0;
    for (std::size_t j = 0; j < spring_q_.size(); ++j) {
      const int v = spring_v_[j];
      // c (q - q_prev) / dt + k (q - rest) = tau (backward Euler; at the first period, static).
      const double c = first_springs_ ? 0.0 : model_.passive_damping[v] / dt_;
      const double value = (c * springs_[j] + model_.passive_stiffness[v] * model_.passive_rest[v] +
                            spring_force_[v]) /
                           (c + model_.passive_stiffness[v]);
      change = std::max(change, std::abs(value - q_[spring_q_[j]]));
      q_[spring_q_[j]] = value;
    }
    if (change < 1e-12)
      break;
  }
  for (std::size_t j = 0; j < spring_q_.size(); ++j)
    springs_[j] = q_[spring_q_[j]];
  first_springs_ = false;
}

void ComEstimator::set_unsensed(const Eigen::Ref<const Eigen::VectorXd>& q) {
  for (int k : unsensed_q_)
    q_[k] = q[k];
}

void ComEstimator::update(const Eigen::Ref<const Eigen::VectorXd>& encoders,
                          const Eigen::Matrix3d& imu_orientation,
                          const std::array<Eigen::Vector3d, 2>& reference_soles,
                          const std::array<multibody::Vector6d, 2>& sole_wrenches) {
  const std::array<double, 2> normal_forces{sole_wrenches[0][2], sole_wrenches[1][2]};
  for (std::size_t j = 0; j < joint_q_.size(); ++j)
    q_[joint_q_[j]] = encoders[j];
  // Base orientation: the IMU's, through the kinematics from the base to the IMU frame.
  q_.head<3>().setZero();
  q_.segment<4>(3) << 0, 0, 0, 1;
  multibody::forward_kinematics(model_, data_, q_);
  const Eigen::Matrix3d imu_in_base =
      multibody::frame_placement(model_, data_, imu_frame_).rotation;
  const Eigen::Quaterniond base(Eigen::Matrix3d(imu_orientation * imu_in_base.transpose()));
  q_.segment<4>(3) << base.x(), base.y(), base.z(), base.w();
  if (parameters_.passive == PassiveJointEstimate::wrench && !spring_q_.empty())
    estimate_springs(sole_wrenches);
  multibody::forward_kinematics(model_, data_, q_);

  const double total = normal_forces[0] + normal_forces[1];
  if (normal_forces[0] >= parameters_.min_contact_force ||
      normal_forces[1] >= parameters_.min_contact_force) {
    for (int foot = 0; foot < 2; ++foot)
      weights_[foot] =
          normal_forces[foot] >= parameters_.min_contact_force ? normal_forces[foot] / total : 0.0;
    const double sum = weights_[0] + weights_[1];
    weights_[0] /= sum;
    weights_[1] /= sum;
  }
  std::array<Eigen::Vector3d, 2> anchors; // a_i = s_i,ref - s_i(q_est; p_b = 0)
  Eigen::Vector3d base_position = Eigen::Vector3d::Zero();
  for (int foot = 0; foot < 2; ++foot) {
    anchors[foot] = reference_soles[foot] -
                    multibody::frame_placement(model_, data_, sole_frames_[foot]).translation;
    base_position += weights_[foot] * anchors[foot];
  }
  for (int foot = 0; foot < 2; ++foot)
    soles_[foot] = reference_soles[foot] - anchors[foot] + base_position;
  const Eigen::Vector3d com_in_base = multibody::center_of_mass(model_, data_);
  const Eigen::Vector3d com = com_in_base + base_position;
  if (first_) {
    com_velocity_.setZero();
    first_ = false;
  } else {
    // The change over the period with this period's weights on both ends: a change of the
    // weights (a support switch) moves the anchor, not the robot.
    Eigen::Vector3d change = com_in_base - com_in_base_;
    for (int foot = 0; foot < 2; ++foot)
      change += weights_[foot] * (anchors[foot] - anchors_[foot]);
    com_velocity_ += filter_ * (change / dt_ - com_velocity_);
  }
  com_ = com;
  q_.head<3>() = base_position;
  com_in_base_ = com_in_base;
  anchors_ = anchors;
}

void ComEstimator::set(const Eigen::Vector3d& com, const Eigen::Vector3d& com_velocity) {
  com_ = com;
  com_velocity_ = com_velocity;
  first_ = false;
}

} // namespace plantar::walking
