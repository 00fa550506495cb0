// Joint order of the HRP-2-like model (models/hrp2/hrp2.urdf).
#pragma once

#include <Eigen/Core>
#include <array>
#include <string>

namespace plantar::walking {

/// Number of actuated joints: legs 6 + 6, chest 2, head 2, arms 7 + 7.
constexpr int n_robot_joints = 30;

/// Index of the first joint of each group in a 30-vector q.
constexpr int right_leg_start = 0;
constexpr int left_leg_start = 6;
constexpr int chest_start = 12;
constexpr int head_start = 14;
constexpr int right_arm_start = 16;
constexpr int left_arm_start = 23;

/// The 30 joint angles [rad] in the order of robot_joint_names().
using RobotAngles = Eigen::Matrix<double, n_robot_joints, 1>;

/// Joint names in the order of q: RLEG_JOINT0..5, LLEG_JOINT0..5, CHEST_JOINT0..1,
/// HEAD_JOINT0..1, RARM_JOINT0..6, LARM_JOINT0..6 (jrl-walkgen HRP2Specificities.xml order).
const std::array<std::string, n_robot_joints>& robot_joint_names();

} // namespace plantar::walking
