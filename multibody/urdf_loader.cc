#include "multibody/urdf_loader.h"

#include <console_bridge/console.h>
#include <urdf_model/model.h>
#include <urdf_parser/urdf_parser.h>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <map>
#include <set>
#include <sstream>
#include <stdexcept>

namespace plantar::multibody {

namespace {

/// Collects urdfdom's console messages so that its errors can be reported.
class CaptureHandler : public console_bridge::OutputHandler {
public:
  void log(const std::string& text, console_bridge::LogLevel level, const char*, int) override {
    if (level >= console_bridge::CONSOLE_BRIDGE_LOG_WARN) {
      messages += (messages.empty() ? "" : "; ") + text;
    }
  }
  std::string messages;
};

SE3 to_se3(const urdf::Pose& pose) {
  double x, y, z, w;
  pose.rotation.getQuaternion(x, y, z, w);
  Eigen::Quaterniond quat(w, x, y, z);
  quat.normalize();
  return SE3(quat.toRotationMatrix(),
             Eigen::Vector3d(pose.position.x, pose.position.y, pose.position.z));
}

class Builder {
public:
  Builder(const urdf::ModelInterface& urdf, const ModelOptions& options, const std::string& source)
      : urdf_(urdf), options_(options), source_(source) {}

  Model build() {
    model_.gravity = options_.gravity;
    check_tree();
    const auto root = urdf_.getRoot();
    if (!root) {
      fail("has no root link");
    }
    if (options_.floating_base) {
      const int base = model_.add_body(0, JointType::FreeFlyer, Eigen::Vector3d::Zero(), SE3(),
                                       Inertia(), "root_joint", root->name);
      visit(*root, base, SE3());
    } else {
      model_.add_world();
      visit_world(*root);
    }
    for (const auto& foot : options_.compliant_ankle.foot_links) {
      if (!made_compliant_.count(foot)) {
        throw std::invalid_argument("compliant ankle: foot link '" + foot + "' not found in " +
                                    source_ + " (or it is the root link)");
      }
    }
    model_.finalize();
    check_masses();
    return model_;
  }

private:
  [[noreturn]] void fail(const std::string& what) const {
    throw std::runtime_error("URDF " + source_ + ": " + what);
  }

  /// A link may be the child of one joint only; a second one closes a kinematic loop.
  void check_tree() const {
    std::map<std::string, std::string> parent_joint;
    for (const auto& [name, joint] : urdf_.joints_) {
      const auto [it, inserted] = parent_joint.emplace(joint->child_link_name, name);
      if (!inserted) {
        fail("link '" + joint->child_link_name + "' is the child of joints '" + it->second +
             "' and '" + name + "': kinematic loop (only trees are supported)");
      }
    }
  }

  void visit_world(const urdf::Link& root) {
    // Fixed base: the root link is the world body.
    model_.frames.push_back(Frame{root.name, 0, SE3()});
    visited_.insert(root.name);
    children(root, 0, SE3());
  }

  void visit(const urdf::Link& link, int body, const SE3& link_in_body) {
    if (!visited_.insert(link.name).second) {
      fail("link '" + link.name + "' reached twice: kinematic loop");
    }
    model_.frames.push_back(Frame{link.name, body, link_in_body});
    if (link.inertial) {
      const auto& in = *link.inertial;
      if (!(in.mass >= 0.0) || !std::isfinite(in.mass)) {
        fail("link '" + link.name + "' has mass " + std::to_string(in.mass) + ", allowed >= 0");
      }
      Eigen::Matrix3d i;
      i << in.ixx, in.ixy, in.ixz, in.ixy, in.iyy, in.iyz, in.ixz, in.iyz, in.izz;
      const Inertia local =
          Inertia(in.mass, Eigen::Vector3d::Zero(), i).transformed(to_se3(in.origin));
      model_.inertia[body] += local.transformed(link_in_body);
    }
    children(link, body, link_in_body);
  }

  void children(const urdf::Link& link, int body, const SE3& link_in_body) {
    for (const auto& joint : link.child_joints) {
      const auto child = urdf_.getLink(joint->child_link_name);
      if (!child) {
        fail("joint '" + joint->name + "' has an unknown child link '" + joint->child_link_name +
             "'");
      }
      const SE3 joint_in_body = link_in_body * to_se3(joint->parent_to_joint_origin_transform);
      const bool compliant = std::find(options_.compliant_ankle.foot_links.begin(),
                                       options_.compliant_ankle.foot_links.end(),
                                       child->name) != options_.compliant_ankle.foot_links.end();
      int child_body = body;
      SE3 child_in_body = joint_in_body;
      switch (joint->type) {
      case urdf::Joint::FIXED:
        break;
      case urdf::Joint::REVOLUTE:
      case urdf::Joint::CONTINUOUS:
      case urdf::Joint::PRISMATIC: {
        const Eigen::Vector3d axis(joint->axis.x, joint->axis.y, joint->axis.z);
        if (!(axis.norm() > 1e-12)) {
          fail("joint '" + joint->name + "' has a zero axis");
        }
        const JointType type =
            joint->type == urdf::Joint::PRISMATIC ? JointType::Prismatic : JointType::Revolute;
        child_body =
            model_.add_body(body, type, axis.normalized(), joint_in_body, Inertia(), joint->name,
                            compliant ? child->name + "_ankle_end" : child->name);
        child_in_body = SE3();
        set_limits(*joint, child_body);
        break;
      }
      default:
        fail("joint '" + joint->name + "' has type " +
             (joint->type == urdf::Joint::FLOATING ? std::string("floating")
              : joint->type == urdf::Joint::PLANAR ? std::string("planar")
                                                   : std::string("unknown")) +
             ": supported types are revolute, continuous, prismatic and fixed");
      }
      if (compliant) {
        std::tie(child_body, child_in_body) =
            add_compliant_ankle(*child, child_body, child_in_body);
      }
      visit(*child, child_body, child_in_body);
    }
  }

  void set_limits(const urdf::Joint& joint, int body) {
    if (!joint.limits) {
      return;
    }
    const int iq = model_.idx_q[body];
    const int iv = model_.idx_v[body];
    if (joint.type != urdf::Joint::CONTINUOUS) {
      if (joint.limits->lower > joint.limits->upper) {
        fail("joint '" + joint.name + "' has lower limit " + std::to_string(joint.limits->lower) +
             " above its upper limit " + std::to_string(joint.limits->upper));
      }
      model_.lower_position_limit[iq] = joint.limits->lower;
      model_.upper_position_limit[iq] = joint.limits->upper;
    }
    if (joint.limits->effort > 0.0) {
      model_.effort_limit[iv] = joint.limits->effort;
    }
    if (joint.limits->velocity > 0.0) {
      model_.velocity_limit[iv] = joint.limits->velocity;
    }
  }

  /// Inserts z, pitch, roll passive joints; returns the foot body and the foot link's
  /// placement in it.
  std::pair<int, SE3> add_compliant_ankle(const urdf::Link& foot, int body,
                                          const SE3& foot_in_body) {
    const auto& p = options_.compliant_ankle;
    if (!(p.linear_stiffness > 0.0) || !(p.angular_stiffness > 0.0) || !(p.linear_damping >= 0.0) ||
        !(p.angular_damping >= 0.0)) {
      std::ostringstream msg;
      msg << "compliant ankle: stiffness must be > 0 and damping >= 0, got linear k = "
          << p.linear_stiffness << " N/m, c = " << p.linear_damping
          << " N s/m, angular k = " << p.angular_stiffness << " N m/rad, c = " << p.angular_damping
          << " N m s/rad";
      throw std::invalid_argument(msg.str());
    }
    made_compliant_.insert(foot.name);
    const SE3 centre = foot_in_body * SE3(Eigen::Matrix3d::Identity(), p.center_in_foot);
    const int bz =
        model_.add_body(body, JointType::Prismatic, Eigen::Vector3d::UnitZ(), centre, Inertia(),
                        foot.name + "_compliance_z", foot.name + "_compliance_z");
    const int bp =
        model_.add_body(bz, JointType::Revolute, Eigen::Vector3d::UnitY(), SE3(), Inertia(),
                        foot.name + "_compliance_pitch", foot.name + "_compliance_pitch");
    const int br = model_.add_body(bp, JointType::Revolute, Eigen::Vector3d::UnitX(), SE3(),
                                   Inertia(), foot.name + "_compliance_roll", foot.name);
    const double k[3] = {p.linear_stiffness, p.angular_stiffness, p.angular_stiffness};
    const double c[3] = {p.linear_damping, p.angular_damping, p.angular_damping};
    const int bodies[3] = {bz, bp, br};
    for (int n = 0; n < 3; ++n) {
      const int iv = model_.idx_v[bodies[n]];
      model_.passive_stiffness[iv] = k[n];
      model_.passive_damping[iv] = c[n];
      model_.actuated[iv] = false;
    }
    return {br, SE3(Eigen::Matrix3d::Identity(), -p.center_in_foot)};
  }

  /// Every body moved by a joint needs mass in its subtree, otherwise M(q) is singular.
  void check_masses() const {
    for (int i = model_.n_bodies - 1; i > 0; --i) {
      double mass = 0.0;
      for (int j = i; j < model_.subtree_end[i]; ++j) {
        mass += model_.inertia[j].mass;
      }
      if (!(mass > 0.0)) {
        fail("link '" + model_.body_names[i] + "' (moved by joint '" + model_.joint_names[i] +
             "') has no <inertial> mass and no massive descendants: an inertia is needed "
             "there (the mass matrix would be singular)");
      }
    }
  }

  const urdf::ModelInterface& urdf_;
  const ModelOptions& options_;
  std::string source_;
  Model model_;
  std::set<std::string> visited_;
  std::set<std::string> made_compliant_;
};

} // namespace

Model build_model_from_urdf_string(const std::string& xml, const ModelOptions& options,
                                   const std::string& source_name) {
  CaptureHandler capture;
  console_bridge::OutputHandler* previous = console_bridge::getOutputHandler();
  console_bridge::useOutputHandler(&capture);
  urdf::ModelInterfaceSharedPtr urdf;
  try {
    urdf = urdf::parseURDF(xml);
  } catch (...) {
    console_bridge::useOutputHandler(previous);
    throw;
  }
  console_bridge::useOutputHandler(previous);
  if (!urdf) {
    throw std::runtime_error("URDF " + source_name + ": rejected by urdfdom: " +
                             (capture.messages.empty() ? "no message" : capture.messages));
  }
  return Builder(*urdf, options, source_name).build();
}

Model build_model_from_urdf(const std::string& path, const ModelOptions& options) {
  std::ifstream file(path);
  if (!file) {
    throw std::runtime_error("URDF file '" + path + "' cannot be opened (missing or unreadable)");
  }
  std::stringstream text;
  text << file.rdbuf();
  return build_model_from_urdf_string(text.str(), options, "'" + path + "'");
}

} // namespace plantar::multibody
