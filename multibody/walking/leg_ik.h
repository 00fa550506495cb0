// Analytic inverse kinematics of a 6-DoF leg with HRP-2's structure (Kajita's closed form, extended
// to a lateral knee offset along the pitch axis).
#pragma once

#include "multibody/walking/leg_geometry.h"

#include <Eigen/Core>
#include <Eigen/Geometry>

namespace plantar::walking {

/// Joint angles (hip yaw, hip roll, hip pitch, knee, ankle pitch, ankle roll) [rad].
using LegAngles = Eigen::Matrix<double, 6, 1>;

/// Solves the leg's inverse kinematics in closed form (S. Kajita et al., "Introduction to
/// Humanoid Robotics", Springer 2014, sec. 2.5.1, with the knee offset d along the pitch axis).
/// With r = R_a^T (p_hip - p_ankle) the hip seen from the ankle frame:
///   beta = sqrt(r_y^2 + r_z^2 - d^2),  alpha = r_x,
///   ankle roll  q5 = atan2(beta r_y + d r_z, -d r_y + beta r_z),
///   knee        q3 = acos((alpha^2 + beta^2 - L1^2 - L2^2) / (2 L1 L2)) (>= 0),
///   ankle pitch q4 = atan2(beta, alpha) - atan2(L1 cos q3 + L2, -L1 sin q3),
///   hip: Rz(q0) Rx(q1) Ry(q2) = R_b^T R_a Rx(-q5) Ry(-q3 - q4).
/// @param leg        geometry from read_leg_geometry.
/// @param body       pose of the base in the world [m].
/// @param sole       pose of the sole frame in the world [m].
/// @param[out] q     the six angles [rad], each in (-pi, pi]; knee >= 0 (forward-bending knee).
/// Branch: beta >= 0, i.e. the hip lies above the ankle along the z axis of the ankle-pitch link
/// (true in any standing or walking posture); with d != 0 and a deeply bent knee a second
/// solution with beta < 0 exists and is not returned.
/// @throws std::runtime_error naming the leg and the hip-ankle distance if the pose is out of
/// reach (distance > L1 + L2 or < |L1 - L2|, or |d| > lateral distance). Joint limits are not
/// checked here (see within_limits). No heap allocation.
void solve_leg_ik(const LegGeometry& leg, const Eigen::Isometry3d& body,
                  const Eigen::Isometry3d& sole, LegAngles& q);

/// Pose of the sole frame for leg angles q, by the same chain (used to verify solve_leg_ik):
/// T = T_body * Trans(hip) Rz(q0) Rx(q1) Ry(q2) Trans(0, d, -L1) Ry(q3) Trans(0, 0, -L2) Ry(q4)
///     Rx(q5) Trans(ankle_to_sole).
Eigen::Isometry3d leg_forward_kinematics(const LegGeometry& leg, const Eigen::Isometry3d& body,
                                         const LegAngles& q);

/// True if lower_limit - margin <= q <= upper_limit + margin for all six joints.
bool within_limits(const LegGeometry& leg, const LegAngles& q, double margin = 0.0);

} // namespace plantar::walking
