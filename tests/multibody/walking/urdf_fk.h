// Test helper: forward kinematics composed directly from the URDF joint
// transforms that urdfdom parsed (origin * rotation about the joint axis),
// independent of plantar_walking's own kinematics.
#pragma once

#include <Eigen/Geometry>
#include <map>
#include <stdexcept>
#include <string>
#include <urdf_model/model.h>
#include <vector>

namespace plantar::walking::testing {

/// Rigid transform of a urdf::Pose (translation + quaternion).
inline Eigen::Isometry3d to_isometry(const urdf::Pose& pose) {
  Eigen::Isometry3d transform = Eigen::Isometry3d::Identity();
  transform.translation() = Eigen::Vector3d(pose.position.x, pose.position.y, pose.position.z);
  double qx, qy, qz, qw;
  pose.rotation.getQuaternion(qx, qy, qz, qw);
  transform.linear() = Eigen::Quaterniond(qw, qx, qy, qz).toRotationMatrix();
  return transform;
}

/// Pose of `link` in the root-link frame for joint angles `q` (by joint name, missing = 0),
/// walking up the parent chain: T = prod_j origin_j * Rot(axis_j, q_j).
inline Eigen::Isometry3d link_pose(const urdf::ModelInterface& model, const std::string& link,
                                   const std::map<std::string, double>& q) {
  Eigen::Isometry3d transform = Eigen::Isometry3d::Identity();
  urdf::LinkConstSharedPtr current = model.getLink(link);
  if (!current)
    throw std::invalid_argument("link_pose: no link '" + link + "'");
  while (current->parent_joint) {
    const urdf::Joint& joint = *current->parent_joint;
    Eigen::Isometry3d joint_transform = to_isometry(joint.parent_to_joint_origin_transform);
    if (joint.type == urdf::Joint::REVOLUTE || joint.type == urdf::Joint::CONTINUOUS) {
      const auto it = q.find(joint.name);
      const double angle = it == q.end() ? 0.0 : it->second;
      const Eigen::Vector3d axis(joint.axis.x, joint.axis.y, joint.axis.z);
      joint_transform = joint_transform * Eigen::AngleAxisd(angle, axis.normalized());
    }
    transform = joint_transform * transform;
    current = model.getLink(joint.parent_link_name);
  }
  return transform;
}

/// Total mass (kg) and centre of mass (root frame) for joint angles q.
inline std::pair<double, Eigen::Vector3d> mass_and_com(const urdf::ModelInterface& model,
                                                       const std::map<std::string, double>& q) {
  double mass = 0.0;
  Eigen::Vector3d moment = Eigen::Vector3d::Zero();
  for (const auto& [name, link] : model.links_) {
    if (!link->inertial)
      continue;
    const Eigen::Isometry3d pose = link_pose(model, name, q);
    const Eigen::Vector3d com_local = to_isometry(link->inertial->origin).translation();
    mass += link->inertial->mass;
    moment += link->inertial->mass * (pose * com_local);
  }
  return {mass, moment / mass};
}

} // namespace plantar::walking::testing
