#include "multibody/model.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

namespace plantar::multibody {

namespace {
int find_name(const std::vector<std::string>& names, const std::string& name, const char* what) {
  for (std::size_t i = 0; i < names.size(); ++i) {
    if (names[i] == name) {
      return static_cast<int>(i);
    }
  }
  throw std::invalid_argument(std::string("Model: no ") + what + " named '" + name + "'");
}

template <typename V> void append(V& vec, int n, double value) {
  const Eigen::Index old = vec.size();
  vec.conservativeResize(old + n);
  vec.tail(n).setConstant(value);
}
} // namespace

int Model::body_id(const std::string& name) const {
  return find_name(body_names, name, "body");
}
int Model::joint_id(const std::string& name) const {
  return find_name(joint_names, name, "joint");
}
int Model::frame_id(const std::string& name) const {
  for (std::size_t i = 0; i < frames.size(); ++i) {
    if (frames[i].name == name) {
      return static_cast<int>(i);
    }
  }
  throw std::invalid_argument("Model: no frame named '" + name + "'");
}

double Model::total_mass() const {
  double m = 0.0;
  for (int i = 1; i < n_bodies; ++i) {
    m += inertia[i].mass;
  }
  return m;
}

Eigen::VectorXd Model::neutral_configuration() const {
  Eigen::VectorXd q = Eigen::VectorXd::Zero(nq);
  for (int i = 1; i < n_bodies; ++i) {
    if (joint_type[i] == JointType::FreeFlyer) {
      q[idx_q[i] + 6] = 1.0; // qw
    }
  }
  return q;
}

void Model::add_world() {
  if (!body_names.empty()) {
    return;
  }
  body_names.push_back("universe");
  joint_names.push_back("universe");
  parent.push_back(-1);
  joint_type.push_back(JointType::Universe);
  joint_axis.push_back(Eigen::Vector3d::Zero());
  joint_placement.push_back(SE3());
  inertia.push_back(Inertia());
  idx_q.push_back(0);
  idx_v.push_back(0);
  nq_joint.push_back(0);
  nv_joint.push_back(0);
  motion_subspace.push_back(Matrix6Xmax6(6, 0));
  n_bodies = 1;
}

int Model::add_body(int parent_body, JointType type, const Eigen::Vector3d& axis,
                    const SE3& placement, const Inertia& body_inertia,
                    const std::string& joint_name, const std::string& body_name) {
  add_world();
  if (parent_body < 0 || parent_body >= n_bodies) {
    throw std::invalid_argument("Model::add_body: joint '" + joint_name + "' has parent body " +
                                std::to_string(parent_body) + ", allowed [0, " +
                                std::to_string(n_bodies) + ")");
  }
  if (type == JointType::FreeFlyer && parent_body != 0) {
    throw std::invalid_argument("Model::add_body: free-flyer joint '" + joint_name +
                                "' must have the world as parent");
  }
  if ((type == JointType::Revolute || type == JointType::Prismatic) &&
      std::abs(axis.norm() - 1.0) > 1e-9) {
    throw std::invalid_argument("Model::add_body: joint '" + joint_name + "' axis norm " +
                                std::to_string(axis.norm()) + ", must be 1");
  }
  const double inf = std::numeric_limits<double>::infinity();
  int joint_nq = 1;
  int joint_nv = 1;
  Matrix6Xmax6 s;
  switch (type) {
  case JointType::FreeFlyer:
    joint_nq = 7;
    joint_nv = 6;
    s = Matrix6d::Identity();
    break;
  case JointType::Revolute:
    s = Vector6d::Zero();
    s.col(0).tail<3>() = axis;
    break;
  case JointType::Prismatic:
    s = Vector6d::Zero();
    s.col(0).head<3>() = axis;
    break;
  default:
    throw std::invalid_argument("Model::add_body: joint '" + joint_name + "' has an invalid type");
  }
  body_names.push_back(body_name);
  joint_names.push_back(joint_name);
  parent.push_back(parent_body);
  joint_type.push_back(type);
  joint_axis.push_back(type == JointType::FreeFlyer ? Eigen::Vector3d::Zero() : axis);
  joint_placement.push_back(placement);
  inertia.push_back(body_inertia);
  idx_q.push_back(nq);
  idx_v.push_back(nv);
  nq_joint.push_back(joint_nq);
  nv_joint.push_back(joint_nv);
  motion_subspace.push_back(s);
  append(lower_position_limit, joint_nq, -inf);
  append(upper_position_limit, joint_nq, inf);
  append(effort_limit, joint_nv, inf);
  append(velocity_limit, joint_nv, inf);
  append(passive_stiffness, joint_nv, 0.0);
  append(passive_damping, joint_nv, 0.0);
  append(passive_rest, joint_nv, 0.0);
  actuated.insert(actuated.end(), joint_nv, type != JointType::FreeFlyer);
  nq += joint_nq;
  nv += joint_nv;
  return n_bodies++;
}

void Model::finalize() {
  add_world();
  subtree_end.assign(n_bodies, 0);
  for (int i = n_bodies - 1; i >= 0; --i) {
    if (subtree_end[i] == 0) {
      subtree_end[i] = i + 1;
    }
    if (i > 0) {
      subtree_end[parent[i]] = std::max(subtree_end[parent[i]], subtree_end[i]);
    }
  }
}

} // namespace plantar::multibody
