#include "apps/compliant_ankle_foot.h"

#include "apps/scene.h"
#include "multibody/walking/ankle_compensation.h"

#include <algorithm>

namespace plantar::app {

std::array<std::string, 3> ankle_spring_joints(const std::string& foot_link) {
  return {foot_link + "_compliance_z", foot_link + "_compliance_pitch",
          foot_link + "_compliance_roll"};
}

CompliantAnkleFoot::CompliantAnkleFoot(const Scene& scene)
    : RigidFoot(scene), robot_(scene.robot) {}

void CompliantAnkleFoot::configure_model(multibody::ModelOptions& options) const {
  const RobotParameters& robot = robot_;
  auto& ankle = options.compliant_ankle;
  ankle.foot_links = {robot.humanoid.foot_links[0], robot.humanoid.foot_links[1]};
  ankle.center_in_foot = robot.ankle_compliance_centre;
  ankle.linear_stiffness = robot.ankle_linear_stiffness;
  ankle.linear_damping = robot.ankle_linear_damping;
  ankle.angular_stiffness = robot.ankle_angular_stiffness;
  ankle.angular_damping = robot.ankle_angular_damping;
}

void CompliantAnkleFoot::plan(const multibody::Model& reference_model,
                              const walking::Humanoid& humanoid,
                              walking::JointReference& reference) {
  const RobotParameters& robot = robot_;
  if (!robot.ankle_deflection_compensation)
    return;
  deflection_ =
      walking::compensate_ankle_deflection(reference_model, humanoid, robot.ankle_compliance_centre,
                                           robot.ankle_angular_stiffness,
                                           robot.ankle_linear_stiffness, reference, robot.leg_ik)
          .deflection;
  period_ = reference.period;
}

void CompliantAnkleFoot::set_reference_state(double t, Eigen::Ref<Eigen::VectorXd> q) const {
  const Eigen::Index n = deflection_.rows();
  if (n == 0)
    return;
  const double position = std::clamp(t / period_, 0.0, double(n - 1));
  const Eigen::Index k = std::min<Eigen::Index>(static_cast<Eigen::Index>(position), n - 1);
  const Eigen::Index k1 = std::min<Eigen::Index>(k + 1, n - 1);
  const double w = position - double(k);
  for (int j = 0; j < 6; ++j)
    q[spring_q_[j]] = (1 - w) * deflection_(k, j) + w * deflection_(k1, j);
}

void CompliantAnkleFoot::add_contacts(double friction) {
  RigidFoot::add_contacts(friction);
  for (int foot = 0; foot < 2; ++foot) {
    const auto joints = ankle_spring_joints(robot_.humanoid.foot_links[foot]);
    for (int i = 0; i < 3; ++i)
      spring_q_[3 * foot + i] = model_->idx_q[model_->joint_id(joints[i])];
  }
}

} // namespace plantar::app
