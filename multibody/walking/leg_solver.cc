#include "multibody/walking/leg_solver.h"

#include "multibody/kinematics.h"

#include <sstream>
#include <stdexcept>

namespace plantar::walking {

LegSolver::LegSolver(const multibody::Model& model, const Humanoid& humanoid, LegSide side,
                     LegIkMethod method)
    : model_(&model), side_(side), joints_(humanoid.leg_joints[static_cast<int>(side)]),
      sole_frame_(humanoid.sole_frames[static_cast<int>(side)]), data_(model),
      q_full_(model.neutral_configuration()) {
  if (method == LegIkMethod::automatic)
    geometry_ = analytic_leg_geometry(model, humanoid, side, why_numerical_);
  else
    why_numerical_ = "the numerical solver was asked for";
  if (!geometry_)
    numerical_ = std::make_unique<NumericalLegIk>(
        model, std::vector<int>(joints_.begin(), joints_.end()), sole_frame_);
}

LegSolver::LegSolver(LegSolver&&) noexcept = default;
LegSolver::~LegSolver() = default;

void LegSolver::set_configuration(const Eigen::Isometry3d& base, const LegAngles& q) {
  if (model_->has_free_base()) {
    q_full_.head<3>() = base.translation();
    const Eigen::Quaterniond rotation(base.linear());
    q_full_.segment<4>(3) << rotation.x(), rotation.y(), rotation.z(), rotation.w();
  }
  for (int k = 0; k < 6; ++k)
    q_full_[model_->idx_q[joints_[k]]] = q[k];
}

void LegSolver::solve(const Eigen::Isometry3d& base, const Eigen::Isometry3d& sole, LegAngles& q) {
  if (numerical_) {
    set_configuration(base, q);
    try {
      numerical_->solve(q_full_, multibody::SE3(sole.linear(), sole.translation()));
    } catch (const std::exception& e) {
      throw std::runtime_error(std::string(to_string(side_)) + " leg: " + e.what());
    }
    for (int k = 0; k < 6; ++k)
      q[k] = q_full_[model_->idx_q[joints_[k]]];
    return;
  }
  solve_leg_ik(*geometry_, base, sole, q);
  for (int i = 0; i < 6; ++i)
    if (q(i) < geometry_->lower_limit(i) || q(i) > geometry_->upper_limit(i)) {
      std::ostringstream msg;
      msg << to_string(side_) << " leg: joint " << geometry_->joint_names[i] << " = " << q(i)
          << " rad is outside its limits [" << geometry_->lower_limit(i) << ", "
          << geometry_->upper_limit(i) << "]";
      throw std::runtime_error(msg.str());
    }
}

Eigen::Isometry3d LegSolver::sole_pose(const Eigen::Isometry3d& base, const LegAngles& q) {
  if (geometry_)
    return leg_forward_kinematics(*geometry_, base, q);
  set_configuration(base, q);
  multibody::forward_kinematics(*model_, data_, q_full_);
  const multibody::SE3 pose = multibody::frame_placement(*model_, data_, sole_frame_);
  Eigen::Isometry3d result = Eigen::Isometry3d::Identity();
  result.linear() = pose.rotation;
  result.translation() = pose.translation;
  return result;
}

} // namespace plantar::walking
