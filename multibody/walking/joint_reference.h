// A sampled whole-body joint reference (q_ref of the 30 joints + base pose) and its
// interpolation for a simulation time step finer than the pattern period.
#pragma once

#include "multibody/walking/robot_joints.h"

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <string>

namespace plantar::walking {

/// Joint reference sampled at a constant period: q_ref for the 30 joints and the pose of BODY
/// (the base of the free-floating joint), for a PD-controlled playback.
struct JointReference {
  double period = 0.005;                                   ///< sample period [s]
  Eigen::VectorXd time;                                    ///< n: t_k = k period [s]
  Eigen::Matrix<double, Eigen::Dynamic, n_robot_joints> q; ///< n x 30 [rad], robot_joint_names()
  Eigen::MatrixX3d base_position;                          ///< n x 3, BODY origin [m]
  Eigen::MatrixX4d base_orientation;                       ///< n x 4, BODY quaternion (w, x, y, z)
  Eigen::MatrixX3d com;                                    ///< n x 3, CoM of the reference [m]
  int n_samples() const { return static_cast<int>(time.size()); }
  double duration() const { return time.size() ? time(time.size() - 1) : 0.0; }
  /// Reference at any time t (for a simulation dt finer than the period): q and the base
  /// position by cubic Hermite interpolation (Catmull-Rom: tangents (x_k+1 - x_k-1) / (2 period),
  /// one-sided at the ends), so that q_ref is C1 and its finite-difference velocity has no jumps
  /// at the samples (linear interpolation gave acceleration spikes growing like 1/dt); exact
  /// for quadratics. Base orientation by slerp. t is clamped to [0, duration]. No heap allocation.
  void sample(double t, RobotAngles& q_out, Eigen::Isometry3d& base_out) const;
  /// Resizes every array for n samples at `sample_period` (time filled with k period).
  void resize(int n, double sample_period);
  /// Stores sample k: base pose, joint angles and CoM.
  void set(int k, const Eigen::Isometry3d& base, const RobotAngles& angles,
           const Eigen::Vector3d& centre_of_mass);
  /// Writes a CSV file: header "t,base_x,base_y,base_z,base_qw,base_qx,base_qy,base_qz,
  /// com_x,com_y,com_z,<30 joint names>", one row per sample (SI units, rad).
  /// @throws std::runtime_error naming the file if it cannot be written.
  void write_csv(const std::string& path) const;
};

} // namespace plantar::walking
