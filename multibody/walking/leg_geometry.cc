#include "multibody/walking/leg_geometry.h"

#include <cmath>
#include <sstream>
#include <stdexcept>

namespace plantar::walking {
namespace {

constexpr double kTolerance = 1e-12;

std::string describe(const Eigen::Vector3d& v) {
  std::ostringstream out;
  out << "(" << v.x() << ", " << v.y() << ", " << v.z() << ")";
  return out.str();
}

} // namespace

std::optional<LegGeometry> analytic_leg_geometry(const multibody::Model& model,
                                                 const Humanoid& humanoid, LegSide side,
                                                 std::string& reason) {
  LegGeometry leg;
  leg.side = side;
  const auto& joints = humanoid.leg_joints[static_cast<int>(side)];
  const Eigen::Vector3d expected_axis[6] = {Eigen::Vector3d::UnitZ(), Eigen::Vector3d::UnitX(),
                                            Eigen::Vector3d::UnitY(), Eigen::Vector3d::UnitY(),
                                            Eigen::Vector3d::UnitY(), Eigen::Vector3d::UnitX()};
  const auto mismatch = [&](int i, const std::string& what) {
    reason = "joint " + leg.joint_names[i] + ": " + what;
    return std::nullopt;
  };
  Eigen::Vector3d origin[6];
  int parent = humanoid.base_body;
  for (int i = 0; i < 6; ++i) {
    const int j = joints[i];
    leg.joint_names[i] = model.joint_names[j];
    if (model.joint_type[j] != multibody::JointType::Revolute)
      return mismatch(i, "is not revolute");
    if (model.parent[j] != parent)
      return mismatch(i, "does not follow the previous leg joint directly");
    parent = j;
    if ((model.joint_axis[j] - expected_axis[i]).norm() > kTolerance)
      return mismatch(i, "axis " + describe(model.joint_axis[j]) + ", the closed form needs " +
                             describe(expected_axis[i]));
    if (!model.joint_placement[j].rotation.isIdentity(kTolerance))
      return mismatch(i, "its frame is rotated; the closed form needs rpy = 0");
    const int iq = model.idx_q[j], iv = model.idx_v[j];
    leg.lower_limit(i) = model.lower_position_limit[iq];
    leg.upper_limit(i) = model.upper_position_limit[iq];
    leg.velocity_limit(i) = model.velocity_limit[iv];
    origin[i] = model.joint_placement[j].translation;
  }
  // Structure needed by the closed form: yaw/roll/pitch intersect, ankle pitch/roll intersect,
  // the knee offset lies in the y-z plane of the thigh, the shank is along -z.
  for (int i : {1, 2, 5})
    if (origin[i].norm() > kTolerance)
      return mismatch(i, "origin " + describe(origin[i]) + " must be zero (axes must intersect)");
  if (std::abs(origin[3].x()) > kTolerance || origin[3].z() >= 0.0)
    return mismatch(3, "origin " + describe(origin[3]) + " must be (0, d, -L1), L1 > 0");
  if (std::abs(origin[4].x()) > kTolerance || std::abs(origin[4].y()) > kTolerance ||
      origin[4].z() >= 0.0)
    return mismatch(4, "origin " + describe(origin[4]) + " must be (0, 0, -L2), L2 > 0");
  leg.hip_offset = origin[0];
  leg.thigh_lateral_offset = origin[3].y();
  leg.thigh_length = -origin[3].z();
  leg.shank_length = -origin[4].z();
  const multibody::Frame& sole = model.frames[humanoid.sole_frames[static_cast<int>(side)]];
  if (sole.body != joints[5] || !sole.placement.rotation.isIdentity(kTolerance)) {
    reason = "sole frame " + sole.name + ": not fixed to the ankle-roll link without rotation";
    return std::nullopt;
  }
  leg.ankle_to_sole = sole.placement.translation;
  return leg;
}

LegGeometry read_leg_geometry(const multibody::Model& model, const Humanoid& humanoid,
                              LegSide side) {
  std::string reason;
  const std::optional<LegGeometry> leg = analytic_leg_geometry(model, humanoid, side, reason);
  if (!leg)
    throw std::runtime_error(std::string("read_leg_geometry: ") + to_string(side) +
                             " leg: " + reason);
  return *leg;
}

} // namespace plantar::walking
