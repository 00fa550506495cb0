// Feed-forward compensation of the static deflection of passive compliant ankles.
#pragma once

#include "multibody/model.h"
#include "multibody/walking/humanoid.h"
#include "multibody/walking/joint_reference.h"
#include "multibody/walking/leg_solver.h"

#include <Eigen/Core>

namespace plantar::walking {

/// Figures of a compensation (rad, N m).
struct AnkleCompensationReport {
  double max_pitch = 0.0;  ///< max |theta_pitch| over the samples and both feet, rad
  double max_roll = 0.0;   ///< max |theta_roll|, rad
  double max_moment = 0.0; ///< max |ground moment about an ankle| (horizontal part), N m
  /// Max over samples of |sum_i F_i - M (c'' - g)|, c the reference's CoM column, N: checks the
  /// point-mass wrench against the whole-body CoM of the reference.
  double max_force_mismatch = 0.0;
  double max_sag = 0.0; ///< max u, m
  /// Predicted spring deflection per sample (n x 6): u (m), theta_p, theta_r (rad) of the right
  /// foot, then of the left foot (0 for a foot in the air).
  Eigen::Matrix<double, Eigen::Dynamic, 6> deflection;
};

/// HRP-2's controller offsets the leg joints by the deflection that the passive ankle spring
/// (rubber bushes) will take under the load the reference itself predicts. Per sample k:
///
/// 1. Ground wrench the reference needs (links as point masses m_i at their CoMs p_i, link
///    rotational inertias neglected; p_i'' by central differences of the samples):
///        F = sum m_i (p_i'' - g),   M_0 = sum m_i p_i x (p_i'' - g),   g = (0, 0, -9.81) m/s^2
///    and its ZMP on z = 0: p = (-M_0,y / F_z, M_0,x / F_z, 0).
/// 2. Feet in support: soles (the humanoid's sole frames) below z = 1e-6 m in the reference. One
///    foot: it takes F at p. Two feet: alpha_L = clamp((p - c_R).(c_L - c_R) / |c_L - c_R|^2,
///    0, 1), alpha_R = 1 - alpha_L (c the sole centres); foot i takes F_i = alpha_i F at
///    p_i = c_i + (p - (c_R + alpha_L (c_L - c_R))) (the sum of the moments is M_0).
/// 3. In the frame of the compliance centre a_i (the foot link frame moved by
///    compliance_centre), with tau_i = (p_i - a_i) x F_i, the spring (passive forces -k q; chain
///    S = Trans(0, 0, u) Ry(theta_p) Rx(theta_r) between the leg and the foot)
///    deflects by
///        u = F_z / k_z,   theta_p = tau_y / k,   theta_r = tau_x / k.
/// 4. The leg is solved again (LegSolver) for the sole target T' = T A^-1 S^-1 A (T the
///    planned sole pose, A the ankle -> sole transform): the rigid leg then ends S^-1 short of
///    the planned foot, and the deflected spring puts the foot exactly on its planned pose.
/// The waist pose, the other joints and the CoM column are unchanged.
///
/// @param model               the robot without compliant ankles, free base
/// @param humanoid            resolved on @p model; the reference's columns are its joints
/// @param compliance_centre   in the foot link frame, m (CompliantAnkleParameters::center_in_foot)
/// @param angular_stiffness   k, N m/rad per foot (pitch and roll), > 0
/// @param linear_stiffness    k_z, N/m per foot, > 0
/// @param reference           modified in place (the leg columns); >= 3 samples
/// @throws std::invalid_argument for a stiffness <= 0 or fewer than 3 samples,
///         std::runtime_error for a sample with no foot on the ground or F_z <= 0, or a
///         compensated leg pose out of reach.
AnkleCompensationReport
compensate_ankle_deflection(const multibody::Model& model, const Humanoid& humanoid,
                            const Eigen::Vector3d& compliance_centre, double angular_stiffness,
                            double linear_stiffness, JointReference& reference,
                            LegIkMethod leg_ik = LegIkMethod::automatic);

} // namespace plantar::walking
