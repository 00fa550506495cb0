#include "multibody/walking/leg_geometry.h"

#include <cmath>
#include <sstream>
#include <stdexcept>
#include <urdf_parser/urdf_parser.h>

namespace plantar::walking {
namespace {

constexpr double kTolerance = 1e-12;

Eigen::Vector3d to_vector(const urdf::Vector3& v) {
  return Eigen::Vector3d(v.x, v.y, v.z);
}

std::string describe(const Eigen::Vector3d& v) {
  std::ostringstream out;
  out << "(" << v.x() << ", " << v.y() << ", " << v.z() << ")";
  return out.str();
}

[[noreturn]] void fail(const std::string& joint, const std::string& what) {
  throw std::runtime_error("read_leg_geometry: joint " + joint + ": " + what);
}

urdf::JointConstSharedPtr get_joint(const urdf::ModelInterface& model, const std::string& name) {
  urdf::JointConstSharedPtr joint = model.getJoint(name);
  if (!joint)
    fail(name, "missing from the URDF");
  double x, y, z, w;
  joint->parent_to_joint_origin_transform.rotation.getQuaternion(x, y, z, w);
  if (std::abs(std::abs(w) - 1.0) > kTolerance)
    fail(name, "origin has a rotation (quaternion w = " + std::to_string(w) +
                   "); the closed-form IK needs rpy = 0");
  return joint;
}

} // namespace

std::shared_ptr<urdf::ModelInterface> load_urdf(const std::string& urdf_path) {
  std::shared_ptr<urdf::ModelInterface> model = urdf::parseURDFFile(urdf_path);
  if (!model)
    throw std::runtime_error("load_urdf: urdfdom could not parse '" + urdf_path + "'");
  return model;
}

LegGeometry read_leg_geometry(const urdf::ModelInterface& model, LegSide side) {
  LegGeometry leg;
  leg.side = side;
  const std::string prefix = side == LegSide::right ? "RLEG" : "LLEG";
  leg.sole_link = side == LegSide::right ? "r_sole" : "l_sole";
  const Eigen::Vector3d expected_axis[6] = {Eigen::Vector3d::UnitZ(), Eigen::Vector3d::UnitX(),
                                            Eigen::Vector3d::UnitY(), Eigen::Vector3d::UnitY(),
                                            Eigen::Vector3d::UnitY(), Eigen::Vector3d::UnitX()};
  Eigen::Vector3d origin[6];
  std::string parent = "BODY";
  for (int i = 0; i < 6; ++i) {
    leg.joint_names[i] = prefix + "_JOINT" + std::to_string(i);
    const urdf::JointConstSharedPtr joint = get_joint(model, leg.joint_names[i]);
    if (joint->type != urdf::Joint::REVOLUTE)
      fail(leg.joint_names[i], "is not revolute");
    if (joint->parent_link_name != parent)
      fail(leg.joint_names[i],
           "parent link is '" + joint->parent_link_name + "', expected '" + parent + "'");
    parent = joint->child_link_name;
    const Eigen::Vector3d axis = to_vector(joint->axis);
    if ((axis - expected_axis[i]).norm() > kTolerance)
      fail(leg.joint_names[i],
           "axis " + describe(axis) + ", expected " + describe(expected_axis[i]));
    if (!joint->limits)
      fail(leg.joint_names[i], "has no <limit>");
    leg.lower_limit(i) = joint->limits->lower;
    leg.upper_limit(i) = joint->limits->upper;
    leg.velocity_limit(i) = joint->limits->velocity;
    origin[i] = to_vector(joint->parent_to_joint_origin_transform.position);
  }
  // Structure needed by the closed form: yaw/roll/pitch intersect, ankle pitch/roll intersect,
  // the knee offset lies in the y-z plane of the thigh, the shank is along -z.
  for (int i : {1, 2, 5})
    if (origin[i].norm() > kTolerance)
      fail(leg.joint_names[i],
           "origin " + describe(origin[i]) + " must be zero (axes must intersect)");
  if (std::abs(origin[3].x()) > kTolerance || origin[3].z() >= 0.0)
    fail(leg.joint_names[3], "origin " + describe(origin[3]) + " must be (0, d, -L1), L1 > 0");
  if (std::abs(origin[4].x()) > kTolerance || std::abs(origin[4].y()) > kTolerance ||
      origin[4].z() >= 0.0)
    fail(leg.joint_names[4], "origin " + describe(origin[4]) + " must be (0, 0, -L2), L2 > 0");
  leg.hip_offset = origin[0];
  leg.thigh_lateral_offset = origin[3].y();
  leg.thigh_length = -origin[3].z();
  leg.shank_length = -origin[4].z();
  // Sole: a fixed joint from the ankle-roll link to the sole link.
  const urdf::LinkConstSharedPtr sole = model.getLink(leg.sole_link);
  if (!sole || !sole->parent_joint)
    throw std::runtime_error("read_leg_geometry: link " + leg.sole_link + " missing or unattached");
  const urdf::JointConstSharedPtr sole_joint = get_joint(model, sole->parent_joint->name);
  if (sole_joint->type != urdf::Joint::FIXED || sole_joint->parent_link_name != parent)
    fail(sole_joint->name, "must be a fixed joint from " + parent + " to " + leg.sole_link);
  leg.ankle_to_sole = to_vector(sole_joint->parent_to_joint_origin_transform.position);
  return leg;
}

} // namespace plantar::walking
