#pragma once
// Centre of mass and divergent component of motion (DCM) of a humanoid from what it senses:
// joint encoders, the IMU's orientation and the feet's normal forces (kinematic-inertial
// estimate anchored on the contact feet, as in Caron et al. 2019's LIPM stabilizer):
//   q_est: the controlled joints from the encoders; the passive joints (compliant ankles' springs,
//          which no encoder reads) at the plan's values (set_unsensed) or, with
//          PassiveJointEstimate::wrench, each spring-damper (k_p, c_p) driven by the sensed foot
//          wrenches, c_p q_p' + k_p (q_p - rest_p) = tau_p = [J_R^T W_R + J_L^T W_L]_p (J_i the
//          sole frame's Jacobian at q_est, W_i the ground's wrench on foot i; the foot's inertia
//          and weight neglected), by backward Euler over the control period (the first period
//          static); a fixed point over q_p, to 1e-12 or 4 passes;
//          base orientation R_b = R_imu (R_b^T R_imu)^T|_kinematics,
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
#include "multibody/spatial.h"
#include "multibody/walking/humanoid.h"

#include <Eigen/Core>

#include <array>

namespace plantar::walking {

/// Where the estimate takes the passive joints (those with a spring, no encoder) from.
enum class PassiveJointEstimate {
  plan,   ///< the values given by set_unsensed (the plan's predicted deflection)
  wrench, ///< each spring-damper driven by the F/T sensors' wrenches
};

struct ComEstimatorParameters {
  double velocity_time_constant = 0.01; ///< tau, s, >= 0 (0: the raw finite difference)
  double min_contact_force = 20;        ///< N: a foot below it does not anchor
  PassiveJointEstimate passive = PassiveJointEstimate::plan;
};

class ComEstimator {
public:
  /// @p model (outlives the estimator) with @p humanoid resolved on it; @p imu_frame a frame of
  /// the model; @p dt the control period (s).
  ComEstimator(const multibody::Model& model, const Humanoid& humanoid, int imu_frame,
               const ComEstimatorParameters& parameters, double dt);
  /// One estimate. @param encoders the controlled joints (Humanoid order, rad);
  /// @param imu_orientation the IMU frame -> world; @param reference_soles the planned sole
  /// positions (right, left; world, m); @param sole_wrenches the ground's wrench on each foot
  /// as its F/T sensor reads it, moved to the sole frame: [f (N); n (N m, about the sole
  /// origin)] in sole axes; f_z is the foot's normal force.
  void update(const Eigen::Ref<const Eigen::VectorXd>& encoders,
              const Eigen::Matrix3d& imu_orientation,
              const std::array<Eigen::Vector3d, 2>& reference_soles,
              const std::array<multibody::Vector6d, 2>& sole_wrenches);
  /// The coordinates no encoder reads (passive joints, e.g. compliant ankles' springs; not the
  /// base) taken from @p q (nq) for the next updates: the plan's predicted values (default: at
  /// rest, neutral); with PassiveJointEstimate::wrench the springs' coordinates are then
  /// replaced by their equilibrium under the sensed wrenches. No heap allocation.
  void set_unsensed(const Eigen::Ref<const Eigen::VectorXd>& q);
  /// Replaces the estimate by a given CoM and CoM velocity (the ground-truth option).
  void set(const Eigen::Vector3d& com, const Eigen::Vector3d& com_velocity);
  const Eigen::Vector3d& com() const { return com_; }                   ///< m, world
  const Eigen::Vector3d& com_velocity() const { return com_velocity_; } ///< m/s, world
  Eigen::Vector3d dcm(double omega) const { return com_ + com_velocity_ / omega; }
  /// The soles (right, left) where the estimate puts them: s_i(q_est; p_b) (world, m); a loaded
  /// sole on its reference position, a swinging one where the kinematics from it say.
  const std::array<Eigen::Vector3d, 2>& soles() const { return soles_; }
  /// The estimate's configuration (nq; base placed as the anchors say).
  const Eigen::VectorXd& configuration() const { return q_; }

private:
  void estimate_springs(const std::array<multibody::Vector6d, 2>& sole_wrenches);

  const multibody::Model& model_;
  ComEstimatorParameters parameters_;
  multibody::Data data_;
  Eigen::VectorXd q_;
  std::vector<int> joint_q_, unsensed_q_;
  std::vector<int> spring_q_, spring_v_; ///< passive joints with a spring (1 dof each)
  Eigen::MatrixXd jacobian_;             ///< 6 x nv
  Eigen::VectorXd spring_force_;         ///< nv: J_R^T W_R + J_L^T W_L
  std::vector<double> springs_;          ///< the springs' last estimate (spring_q_ order)
  bool first_springs_ = true;
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
