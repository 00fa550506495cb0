#pragma once
// Foot form "compliant ankle": the rigid outline points (rigid_foot.h) under a passive 3-DoF
// spring-damper between each foot link and its ankle (z, pitch, roll; paper eq. 13, built by
// multibody::ModelOptions::compliant_ankle from Robot/Ankle *). With Robot/Ankle deflection
// compensation the reference is compensated (multibody/walking/ankle_compensation.h) and
// the run starts with the springs at their predicted deflection.

#include "apps/humanoid_parameters.h"
#include "apps/rigid_foot.h"

#include <string>

namespace plantar::app {

/// The spring joints that multibody/urdf_loader.cc inserts above @p foot_link: z, pitch, roll.
std::array<std::string, 3> ankle_spring_joints(const std::string& foot_link);

class CompliantAnkleFoot : public RigidFoot {
public:
  explicit CompliantAnkleFoot(const Scene& scene);
  void configure_model(multibody::ModelOptions& options) const override;
  void plan(const multibody::Model& reference_model, const walking::Humanoid& humanoid,
            walking::JointReference& reference) override;
  /// Compensated ankles: the springs at the deflection the compensation predicts at t (linear
  /// between the reference's samples, t clamped to them); else leaves @p q.
  void set_reference_state(double t, Eigen::Ref<Eigen::VectorXd> q) const override;
  /// The ankle's angular springs (roll and pitch).
  Eigen::Vector2d tilt_stiffness() const override {
    return Eigen::Vector2d::Constant(robot_.ankle_angular_stiffness);
  }
  /// foot_stiffness: the ankle's linear spring (in series with rigid contacts).
  void summarize(HumanoidSummary& summary) const override {
    summary.foot_stiffness = robot_.ankle_linear_stiffness;
  }

protected:
  /// The rigid contacts, then the springs' coordinates in q.
  void add_contacts(double friction) override;

private:
  RobotParameters robot_;
  std::array<int, 6> spring_q_{}; ///< idx_q of (z, pitch, roll) of the right, then left foot
  /// Compensated ankles: the predicted deflection (u, theta_p, theta_r of the right, then the
  /// left foot) at every sample of the reference (n x 6; empty: none) and its period (s).
  Eigen::Matrix<double, Eigen::Dynamic, 6> deflection_;
  double period_ = 0;
};

} // namespace plantar::app
