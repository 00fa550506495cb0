#include "multibody/walking/leg_ik.h"

#include <algorithm>
#include <cmath>
#include <sstream>
#include <stdexcept>

namespace plantar::walking {
namespace {

using Eigen::AngleAxisd;
using Eigen::Vector3d;

[[noreturn]] void out_of_reach(const LegGeometry& leg, const std::string& what, double value,
                               double lower, double upper) {
  std::ostringstream msg;
  msg << "solve_leg_ik: " << to_string(leg.side) << " leg: " << what << " = " << value
      << " m is outside the reachable range [" << lower << ", " << upper << "]";
  throw std::runtime_error(msg.str());
}

} // namespace

void solve_leg_ik(const LegGeometry& leg, const Eigen::Isometry3d& body,
                  const Eigen::Isometry3d& sole, LegAngles& q) {
  const double L1 = leg.thigh_length, L2 = leg.shank_length, d = leg.thigh_lateral_offset;
  const Eigen::Matrix3d Ra = sole.linear(); // ankle frame = sole frame orientation
  const Vector3d p_ankle = sole.translation() - Ra * leg.ankle_to_sole;
  const Vector3d p_hip = body * leg.hip_offset;
  const Vector3d r = Ra.transpose() * (p_hip - p_ankle);
  const double lateral_sq = r.y() * r.y() + r.z() * r.z() - d * d;
  if (lateral_sq < 0.0)
    out_of_reach(leg, "hip-ankle distance in the ankle y-z plane",
                 std::sqrt(r.y() * r.y() + r.z() * r.z()), std::abs(d), L1 + L2);
  // Branch beta >= 0: the hip is above the ankle along the z axis of the ankle-pitch link (every
  // standing or walking posture). The other branch (beta < 0, deep squats) is not returned.
  const double beta = std::sqrt(lateral_sq);
  const double alpha = r.x();
  const double planar = std::hypot(alpha, beta);
  // Allow round-off at full extension.
  const double slack = 1e-12 * (L1 + L2);
  if (planar > L1 + L2 + slack || planar < std::abs(L1 - L2) - slack)
    out_of_reach(leg, "hip-ankle distance in the leg plane", planar, std::abs(L1 - L2), L1 + L2);
  const double denom = d * d + beta * beta;
  q(5) = std::atan2((beta * r.y() + d * r.z()) / denom, (-d * r.y() + beta * r.z()) / denom);
  const double cos_knee =
      std::clamp((planar * planar - L1 * L1 - L2 * L2) / (2.0 * L1 * L2), -1.0, 1.0);
  q(3) = std::acos(cos_knee);
  double ankle_pitch =
      std::atan2(beta, alpha) - std::atan2(L1 * std::cos(q(3)) + L2, -L1 * std::sin(q(3)));
  ankle_pitch = std::remainder(ankle_pitch, 2.0 * M_PI);
  q(4) = ankle_pitch;
  // Hip rotation M = Rz(q0) Rx(q1) Ry(q2):
  //   M = [[.., -sin q0 cos q1, ..], [.., cos q0 cos q1, ..], [-cos q1 sin q2, sin q1, cos q1 cos
  //   q2]]
  const Eigen::Matrix3d M = body.linear().transpose() * Ra *
                            AngleAxisd(-q(5), Vector3d::UnitX()).toRotationMatrix() *
                            AngleAxisd(-q(3) - q(4), Vector3d::UnitY()).toRotationMatrix();
  q(0) = std::atan2(-M(0, 1), M(1, 1));
  q(1) = std::atan2(M(2, 1), std::hypot(M(0, 1), M(1, 1)));
  q(2) = std::atan2(-M(2, 0), M(2, 2));
}

Eigen::Isometry3d leg_forward_kinematics(const LegGeometry& leg, const Eigen::Isometry3d& body,
                                         const LegAngles& q) {
  Eigen::Isometry3d t = body;
  t.translate(leg.hip_offset);
  t.rotate(AngleAxisd(q(0), Vector3d::UnitZ()));
  t.rotate(AngleAxisd(q(1), Vector3d::UnitX()));
  t.rotate(AngleAxisd(q(2), Vector3d::UnitY()));
  t.translate(Vector3d(0.0, leg.thigh_lateral_offset, -leg.thigh_length));
  t.rotate(AngleAxisd(q(3), Vector3d::UnitY()));
  t.translate(Vector3d(0.0, 0.0, -leg.shank_length));
  t.rotate(AngleAxisd(q(4), Vector3d::UnitY()));
  t.rotate(AngleAxisd(q(5), Vector3d::UnitX()));
  t.translate(leg.ankle_to_sole);
  return t;
}

bool within_limits(const LegGeometry& leg, const LegAngles& q, double margin) {
  return ((q - leg.lower_limit).array() >= -margin).all() &&
         ((leg.upper_limit - q).array() >= -margin).all();
}

} // namespace plantar::walking
