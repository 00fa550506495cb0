// A sampled whole-body joint reference (q_ref of the controlled joints + base pose) and its
// interpolation for a simulation time step finer than the pattern period.
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <string>
#include <vector>

namespace plantar::walking {

/// Joint reference sampled at a constant period: q_ref for the controlled joints (Humanoid) and
/// the pose of the base (the free-floating joint), for a PD-controlled playback.
struct JointReference {
  double period = 0.005;                ///< sample period [s]
  Eigen::VectorXd time;                 ///< n: t_k = k period [s]
  Eigen::MatrixXd q;                    ///< n x joints [rad], joint_names order
  std::vector<std::string> joint_names; ///< the columns of q
  Eigen::MatrixX3d base_position;       ///< n x 3, base origin [m]
  Eigen::MatrixX4d base_orientation;    ///< n x 4, base quaternion (w, x, y, z)
  Eigen::MatrixX3d com;                 ///< n x 3, CoM of the reference [m]
  /// n x 2, planned ground height under the right and left soles [m] (FootstepPlan::ground;
  /// zeros for references planned on flat ground).
  Eigen::MatrixX2d ground;
  /// The plan's support polygons and, n x 2, the one each sole (right, left) is on or swings
  /// to (FootstepPlan::supports, support_index; empty for references without them).
  std::vector<Eigen::Matrix2Xd> supports;
  Eigen::MatrixX2i support_index;
  /// n x 2, each sole's swing: horizontal progress in [0, 1] and planned touchdown time [s],
  /// -1 while it is down (FootstepPlan::swing_progress, swing_end; empty: no swings planned).
  Eigen::MatrixX2d swing_progress, swing_end;
  int n_samples() const { return static_cast<int>(time.size()); }
  double duration() const { return time.size() ? time(time.size() - 1) : 0.0; }
  /// Reference at any time t (for a simulation dt finer than the period): q and the base
  /// position by cubic Hermite interpolation (Catmull-Rom: tangents (x_k+1 - x_k-1) / (2 period),
  /// one-sided at the ends), so that q_ref is C1 and its finite-difference velocity has no jumps
  /// at the samples (linear interpolation gave acceleration spikes growing like 1/dt); exact
  /// for quadratics. Base orientation by slerp. t is clamped to [0, duration]. No heap allocation.
  /// @param q_out  size joint_names.size().
  void sample(double t, Eigen::Ref<Eigen::VectorXd> q_out, Eigen::Isometry3d& base_out) const;
  /// Planned ground heights (right, left) at t [m], linear between samples, t clamped.
  Eigen::Vector2d ground_at(double t) const;
  /// The support polygon of sole @p foot (0 right, 1 left) at t (the nearer sample), in the
  /// sole frame [m]; nullptr when none is planned (empty: the whole sole).
  const Eigen::Matrix2Xd* support_at(int foot, double t) const;
  /// Sole @p foot's (0 right, 1 left) swing at t: (progress, planned touchdown time [s]),
  /// progress linear between samples; (-1, -1) while it is down at the nearer sample or when
  /// none is planned.
  Eigen::Vector2d swing_at(int foot, double t) const;
  /// Resizes every array for n samples at `sample_period` (time filled with k period) and
  /// the joints @p names; ground is set to zero.
  void resize(int n, double sample_period, const std::vector<std::string>& names);
  /// Stores sample k: base pose, joint angles and CoM.
  void set(int k, const Eigen::Isometry3d& base, const Eigen::Ref<const Eigen::VectorXd>& angles,
           const Eigen::Vector3d& centre_of_mass);
  /// Writes a CSV file: header "t,base_x,base_y,base_z,base_qw,base_qx,base_qy,base_qz,
  /// com_x,com_y,com_z,<joint names>", one row per sample (SI units, rad).
  /// @throws std::runtime_error naming the file if it cannot be written.
  void write_csv(const std::string& path) const;

private:
  /// The samples k, k1 = min(k + 1, n - 1) around t (clamped to [0, duration]) and the weight
  /// w in [0, 1] of k1. n_samples() > 0.
  void interval(double t, int& k, int& k1, double& w) const;
};

} // namespace plantar::walking
