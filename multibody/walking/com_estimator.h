#pragma once
// Centre of mass and divergent component of motion (DCM) of a humanoid from what it senses:
// joint encoders, the IMU's orientation and the feet's normal forces (kinematic-inertial
// estimate anchored on the contact feet, as in Caron et al. 2019's LIPM stabilizer):
//   q_est: the controlled joints from the encoders (passive joints, e.g. compliant ankles, at
//          rest: not sensed), base orientation R_b = R_imu (R_b^T R_imu)^T|_kinematics,
//          base position p_b so that the force-weighted anchor of the soles sits on the
//          reference's:  p_b = sum_i w_i (s_i,ref - s_i(q_est; p_b = 0)),  w_i = f_i / sum f
//          (feet with f_i < min_contact_force do not anchor; no loaded foot: the last weights)
//   c = CoM(q_est),  c' = low-pass (time constant tau) of the change over the period with
//          the weights of its end on both ends, (CoM_0(q_n) - CoM_0(q_n-1) + sum_i w_i,n (a_i,n -
//          a_i,n-1)) / dt (CoM_0: base at the origin; a_i = s_i,ref - s_i(q_est; p_b = 0)):
//          a support switch moves the anchor, not the estimated velocity,
//   DCM xi = c + c' / omega,  omega = sqrt(g / z_c).
// Everything is sized by the constructor; update() allocates nothing.

#include "multibody/data.h"
#include "multibody/model.h"
#include "multibody/walking/humanoid.h"

#include <Eigen/Core>

#include <array>

namespace plantar::walking {

struct ComEstimatorParameters {
  double velocity_time_constant = 0.01; ///< tau, s, >= 0 (0: the raw finite difference)
  double min_contact_force = 20;        ///< N: a foot below it does not anchor
};

class ComEstimator {
public:
  /// @p model (outlives the estimator) with @p humanoid resolved on it; @p imu_frame a frame of
  /// the model; @p dt the control period (s).
  ComEstimator(const multibody::Model& model, const Humanoid& humanoid, int imu_frame,
               const ComEstimatorParameters& parameters, double dt);
  /// One estimate. @param encoders the controlled joints (Humanoid order, rad);
  /// @param imu_orientation the IMU frame -> world; @param reference_soles the planned sole
  /// positions (right, left; world, m); @param normal_forces the feet's measured normal forces
  /// (N).
  void update(const Eigen::Ref<const Eigen::VectorXd>& encoders,
              const Eigen::Matrix3d& imu_orientation,
              const std::array<Eigen::Vector3d, 2>& reference_soles,
              const std::array<double, 2>& normal_forces);
  /// The coordinates no encoder reads (passive joints, e.g. compliant ankles' springs; not the
  /// base) taken from @p q (nq) for the next updates: the plan's predicted values (default: at
  /// rest, neutral). No heap allocation.
  void set_unsensed(const Eigen::Ref<const Eigen::VectorXd>& q);
  /// Replaces the estimate by a given CoM and CoM velocity (the ground-truth option).
  void set(const Eigen::Vector3d& com, const Eigen::Vector3d& com_velocity);
  const Eigen::Vector3d& com() const { return com_; }                   ///< m, world
  const Eigen::Vector3d& com_velocity() const { return com_velocity_; } ///< m/s, world
  Eigen::Vector3d dcm(double omega) const { return com_ + com_velocity_ / omega; }
  /// The soles (right, left) where the estimate puts them: s_i(q_est; p_b) (world, m); a loaded
  /// sole on its reference position, a swinging one where the kinematics from it say.
  const std::array<Eigen::Vector3d, 2>& soles() const { return soles_; }

private:
  const multibody::Model& model_;
  ComEstimatorParameters parameters_;
  multibody::Data data_;
  Eigen::VectorXd q_;
  std::vector<int> joint_q_, unsensed_q_;
  int imu_frame_;
  std::array<int, 2> sole_frames_;
  double dt_, filter_;
  bool first_ = true;
  std::array<double, 2> weights_{0.5, 0.5};
  Eigen::Vector3d com_ = Eigen::Vector3d::Zero(), com_velocity_ = Eigen::Vector3d::Zero();
  Eigen::Vector3d com_in_base_ = Eigen::Vector3d::Zero(); ///< CoM(q_est; p_b = 0), last period
  std::array<Eigen::Vector3d, 2> anchors_{Eigen::Vector3d::Zero(), Eigen::Vector3d::Zero()};
  std::array<Eigen::Vector3d, 2> soles_{Eigen::Vector3d::Zero(), Eigen::Vector3d::Zero()};
};

} // namespace plantar::walking
