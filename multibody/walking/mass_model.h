// Whole-body centre of mass of the URDF model, for placing the waist under a CoM reference.
#pragma once

#include "multibody/walking/robot_joints.h"

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <string>
#include <urdf_model/model.h>
#include <vector>

namespace plantar::walking {

/// Constant kinematic tree with masses (Model part): links in topological order (parents first).
struct MassModel {
  struct Body {
    int parent = -1;                ///< index in bodies, -1 for BODY (the root)
    Eigen::Isometry3d joint_origin; ///< parent link frame -> joint frame
    Eigen::Vector3d axis;           ///< revolute axis in the joint frame (unit)
    int q_index = -1;               ///< index in the 30-vector q, -1 for fixed joints / root
    double mass = 0.0;              ///< [kg]
    Eigen::Vector3d com = Eigen::Vector3d::Zero(); ///< in the link frame [m]
    std::string name;
  };
  std::vector<Body> bodies;
  double total_mass = 0.0;
};

/// Builds the mass model from a parsed URDF whose revolute joints are exactly the 30
/// robot_joint_names(). @throws std::runtime_error naming a missing or unexpected joint.
MassModel make_mass_model(const urdf::ModelInterface& model);

/// Workspace for centre_of_mass (Data part): one pose per body.
struct MassModelData {
  explicit MassModelData(const MassModel& model) : poses(model.bodies.size()) {}
  std::vector<Eigen::Isometry3d> poses;
};

/// CoM in the world [m]: c = sum_i m_i (T_i com_i) / M with T_i = T_parent * origin_i * Rot(axis_i,
/// q_i).
/// @param base  pose of BODY in the world; @param q  30 joint angles [rad]. No heap allocation.
Eigen::Vector3d centre_of_mass(const MassModel& model, MassModelData& data,
                               const Eigen::Isometry3d& base,
                               const Eigen::Matrix<double, n_robot_joints, 1>& q);

} // namespace plantar::walking
