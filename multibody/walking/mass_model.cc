#include "multibody/walking/mass_model.h"

#include <map>
#include <stdexcept>

namespace plantar::walking {

MassModel make_mass_model(const urdf::ModelInterface& model) {
  std::map<std::string, int> q_index;
  for (int i = 0; i < n_robot_joints; ++i)
    q_index[robot_joint_names()[i]] = i;
  MassModel result;
  // Breadth-first from the root so that parents come first.
  std::vector<std::pair<urdf::LinkConstSharedPtr, int>> queue = {{model.getRoot(), -1}};
  if (!queue.front().first)
    throw std::runtime_error("make_mass_model: the URDF has no root link");
  int n_revolute = 0;
  for (size_t head = 0; head < queue.size(); ++head) {
    const auto [link, parent] = queue[head];
    MassModel::Body body;
    body.name = link->name;
    body.parent = parent;
    body.joint_origin = Eigen::Isometry3d::Identity();
    body.axis = Eigen::Vector3d::UnitZ();
    if (link->parent_joint) {
      const urdf::Joint& joint = *link->parent_joint;
      const auto& pose = joint.parent_to_joint_origin_transform;
      double x, y, z, w;
      pose.rotation.getQuaternion(x, y, z, w);
      body.joint_origin.linear() = Eigen::Quaterniond(w, x, y, z).toRotationMatrix();
      body.joint_origin.translation() =
          Eigen::Vector3d(pose.position.x, pose.position.y, pose.position.z);
      if (joint.type == urdf::Joint::REVOLUTE || joint.type == urdf::Joint::CONTINUOUS) {
        const auto it = q_index.find(joint.name);
        if (it == q_index.end())
          throw std::runtime_error("make_mass_model: revolute joint '" + joint.name +
                                   "' is not one of the 30 robot joints");
        body.q_index = it->second;
        body.axis = Eigen::Vector3d(joint.axis.x, joint.axis.y, joint.axis.z).normalized();
        ++n_revolute;
      } else if (joint.type != urdf::Joint::FIXED) {
        throw std::runtime_error("make_mass_model: joint '" + joint.name +
                                 "' is neither revolute nor fixed");
      }
    }
    if (link->inertial) {
      body.mass = link->inertial->mass;
      const auto& c = link->inertial->origin.position;
      body.com = Eigen::Vector3d(c.x, c.y, c.z);
    }
    result.total_mass += body.mass;
    const int index = static_cast<int>(result.bodies.size());
    result.bodies.push_back(body);
    for (const auto& child : link->child_links)
      queue.push_back({child, index});
  }
  if (n_revolute != n_robot_joints)
    throw std::runtime_error("make_mass_model: found " + std::to_string(n_revolute) +
                             " revolute joints, expected " + std::to_string(n_robot_joints));
  if (!(result.total_mass > 0.0))
    throw std::runtime_error("make_mass_model: total mass is not positive");
  return result;
}

Eigen::Vector3d centre_of_mass(const MassModel& model, MassModelData& data,
                               const Eigen::Isometry3d& base,
                               const Eigen::Matrix<double, n_robot_joints, 1>& q) {
  Eigen::Vector3d moment = Eigen::Vector3d::Zero();
  for (size_t i = 0; i < model.bodies.size(); ++i) {
    const MassModel::Body& body = model.bodies[i];
    if (body.parent < 0) {
      data.poses[i] = base;
    } else {
      data.poses[i] = data.poses[body.parent] * body.joint_origin;
      if (body.q_index >= 0)
        data.poses[i].rotate(Eigen::AngleAxisd(q(body.q_index), body.axis));
    }
    moment += body.mass * (data.poses[i] * body.com);
  }
  return moment / model.total_mass;
}

} // namespace plantar::walking
