#pragma once
// The articulated rigid-body model, constant after loading (Pinocchio's Model).
//
// Bodies are numbered 0..n_bodies-1; body 0 is the world ("universe").
// Joint i (i >= 1) moves body i relative to its parent body parent[i] < i.
// Body i's frame is the frame of joint i (URDF: the child link frame).
//
// Configuration q (size nq) and velocity v (size nv):
//   free-floating base (joint 1): q = [x y z (world, m), qx qy qz qw (unit quaternion)],
//                                 v = [v_lin, w] of the base, in the BASE (local) frame;
//   revolute / continuous: one angle (rad), prismatic: one displacement (m).
// Fixed URDF joints are merged: their child link's inertia is lumped into the parent
// body and the link is kept as a named Frame.

#include "multibody/spatial.h"

#include <Eigen/Core>
#include <string>
#include <vector>

namespace plantar::multibody {

enum class JointType { Universe, FreeFlyer, Revolute, Prismatic };

/// A named frame rigidly attached to a body (a URDF link, merged or not).
struct Frame {
  std::string name;
  int body = 0;  ///< body index
  SE3 placement; ///< frame -> body coordinates
};

struct Model {
  int n_bodies = 1;                         ///< including the world body 0
  int nq = 0;                               ///< configuration size
  int nv = 0;                               ///< velocity size (degrees of freedom)
  Eigen::Vector3d gravity{0.0, 0.0, -9.81}; ///< m/s^2, world frame

  // Per body / joint (index i; entries for i = 0 are the world's, unused).
  std::vector<std::string> body_names;  ///< URDF link name of the body's root link
  std::vector<std::string> joint_names; ///< URDF joint name (or generated name)
  std::vector<int> parent;              ///< parent body, parent[i] < i
  std::vector<JointType> joint_type;
  std::vector<Eigen::Vector3d> joint_axis;   ///< unit axis in the joint frame (1-DoF joints)
  std::vector<SE3> joint_placement;          ///< joint frame at q = 0 -> parent body frame
  std::vector<Inertia> inertia;              ///< body inertia (merged links included)
  std::vector<int> idx_q, idx_v;             ///< first index of joint i in q and v
  std::vector<int> nq_joint, nv_joint;       ///< sizes of joint i in q and v
  std::vector<Matrix6Xmax6> motion_subspace; ///< S_i (6 x nv_i) in body i's frame
  std::vector<int> subtree_end;              ///< bodies of i's subtree are [i, subtree_end[i])

  std::vector<Frame> frames; ///< every URDF link, by name

  // Limits (URDF <limit>); infinite when absent (continuous joints, base).
  Eigen::VectorXd lower_position_limit; ///< nq
  Eigen::VectorXd upper_position_limit; ///< nq
  Eigen::VectorXd effort_limit;         ///< nv, N or N m
  Eigen::VectorXd velocity_limit;       ///< nv, m/s or rad/s

  // Passive spring-dampers on single-DoF joints (compliant ankles), zero elsewhere:
  // tau_passive = -stiffness (q - rest) - damping v.
  Eigen::VectorXd passive_stiffness; ///< nv, N/m or N m/rad
  Eigen::VectorXd passive_damping;   ///< nv, N s/m or N m s/rad
  Eigen::VectorXd passive_rest;      ///< nv, rest position of each single-DoF joint
  std::vector<bool> actuated;        ///< nv: false for the base and passive joints

  bool has_free_base() const { return n_bodies > 1 && joint_type[1] == JointType::FreeFlyer; }
  /// Index of the body, joint or frame with that name; throws std::invalid_argument if absent.
  int body_id(const std::string& name) const;
  int joint_id(const std::string& name) const;
  int frame_id(const std::string& name) const;
  /// Total mass, kg.
  double total_mass() const;
  /// Neutral configuration: base at the origin with identity orientation, joints at 0.
  Eigen::VectorXd neutral_configuration() const;
  /// Appends a body moved by a joint; used by the URDF loader and by tests building
  /// models by hand. Returns the new body index.
  int add_body(int parent_body, JointType type, const Eigen::Vector3d& axis, const SE3& placement,
               const Inertia& body_inertia, const std::string& joint_name,
               const std::string& body_name);
  /// Fills subtree_end; call once after the last add_body. Bodies must have been added in
  /// depth-first order (each subtree contiguous), as the URDF loader does.
  void finalize();
  /// Creates the world body 0 if the model has no body yet.
  void add_world();
};

} // namespace plantar::multibody
