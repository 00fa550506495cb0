#include "multibody/walking/ankle_compensation.h"

#include "multibody/walking/leg_ik.h"
#include "multibody/walking/mass_model.h"

#include <Eigen/Geometry>

#include <algorithm>
#include <array>
#include <cmath>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

namespace plantar::walking {
namespace {

int body_index(const MassModel& model, const std::string& name) {
  for (size_t i = 0; i < model.bodies.size(); ++i)
    if (model.bodies[i].name == name)
      return static_cast<int>(i);
  throw std::runtime_error("compensate_ankle_deflection: link '" + name +
                           "' not found in the URDF");
}

Eigen::Isometry3d base_pose(const JointReference& reference, int k) {
  Eigen::Isometry3d base = Eigen::Isometry3d::Identity();
  const auto& o = reference.base_orientation;
  base.linear() = Eigen::Quaterniond(o(k, 0), o(k, 1), o(k, 2), o(k, 3)).toRotationMatrix();
  base.translation() = reference.base_position.row(k).transpose();
  return base;
}

} // namespace

AnkleCompensationReport compensate_ankle_deflection(const urdf::ModelInterface& urdf,
                                                    double angular_stiffness,
                                                    double linear_stiffness,
                                                    JointReference& reference) {
  if (!(angular_stiffness > 0.0) || !(linear_stiffness > 0.0)) {
    std::ostringstream msg;
    msg << "compensate_ankle_deflection: angular stiffness " << angular_stiffness
        << " N m/rad and linear stiffness " << linear_stiffness << " N/m must be > 0";
    throw std::invalid_argument(msg.str());
  }
  const int n = reference.n_samples();
  if (n < 3)
    throw std::invalid_argument("compensate_ankle_deflection: the reference has " +
                                std::to_string(n) + " samples, at least 3 are needed");
  const MassModel model = make_mass_model(urdf);
  MassModelData data(model);
  const int nb = static_cast<int>(model.bodies.size());
  const std::array<int, 2> sole = {body_index(model, "r_sole"), body_index(model, "l_sole")};
  const std::array<int, 2> ankle = {body_index(model, "RLEG_LINK5"),
                                    body_index(model, "LLEG_LINK5")};
  const std::array<LegGeometry, 2> legs = {read_leg_geometry(urdf, LegSide::right),
                                           read_leg_geometry(urdf, LegSide::left)};

  // Link CoM positions (3 x bodies per sample), sole and ankle poses, from the original q.
  std::vector<Eigen::Matrix3Xd> points(n, Eigen::Matrix3Xd(3, nb));
  std::vector<std::array<Eigen::Isometry3d, 2>> soles(n), ankles(n);
  for (int k = 0; k < n; ++k) {
    const RobotAngles q = reference.q.row(k).transpose();
    centre_of_mass(model, data, base_pose(reference, k), q);
    for (int i = 0; i < nb; ++i)
      points[k].col(i) = data.poses[i] * model.bodies[i].com;
    for (int foot = 0; foot < 2; ++foot) {
      soles[k][foot] = data.poses[sole[foot]];
      ankles[k][foot] = data.poses[ankle[foot]];
    }
  }

  const double T = reference.period;
  const Eigen::Vector3d g(0.0, 0.0, -9.81);
  AnkleCompensationReport report;
  report.deflection = Eigen::Matrix<double, Eigen::Dynamic, 6>::Zero(n, 6);
  for (int k = 0; k < n; ++k) {
    const int k0 = std::clamp(k, 1, n - 2); // one-sided at the ends (standing samples)
    Eigen::Vector3d force = Eigen::Vector3d::Zero(), moment = Eigen::Vector3d::Zero();
    for (int i = 0; i < nb; ++i) {
      const double m = model.bodies[i].mass;
      if (m == 0.0)
        continue;
      const Eigen::Vector3d a =
          (points[k0 + 1].col(i) - 2.0 * points[k0].col(i) + points[k0 - 1].col(i)) / (T * T);
      force += m * (a - g);
      moment += m * points[k].col(i).cross(a - g);
    }
    {
      const Eigen::Vector3d com_acceleration =
          (reference.com.row(k0 + 1) - 2.0 * reference.com.row(k0) + reference.com.row(k0 - 1))
              .transpose() /
          (T * T);
      report.max_force_mismatch = std::max(
          report.max_force_mismatch, (force - model.total_mass * (com_acceleration - g)).norm());
    }
    if (!(force.z() > 0.0)) {
      std::ostringstream msg;
      msg << "compensate_ankle_deflection: t = " << reference.time(k)
          << " s: the reference needs a vertical ground force " << force.z() << " N <= 0";
      throw std::runtime_error(msg.str());
    }
    const Eigen::Vector3d zmp(-moment.y() / force.z(), moment.x() / force.z(), 0.0);

    std::array<bool, 2> support;
    std::array<Eigen::Vector3d, 2> centre;
    for (int foot = 0; foot < 2; ++foot) {
      centre[foot] = soles[k][foot].translation();
      support[foot] = centre[foot].z() < 1e-6;
      centre[foot].z() = 0.0;
    }
    std::array<double, 2> share = {1.0, 0.0};
    Eigen::Vector3d offset = Eigen::Vector3d::Zero(); // p - projection on the feet segment
    if (support[0] && support[1]) {
      const Eigen::Vector3d d = centre[1] - centre[0];
      share[1] = std::clamp((zmp - centre[0]).dot(d) / d.squaredNorm(), 0.0, 1.0);
      share[0] = 1.0 - share[1];
      offset = zmp - (centre[0] + share[1] * d);
    } else if (support[1]) {
      share = {0.0, 1.0};
    } else if (!support[0]) {
      std::ostringstream msg;
      msg << "compensate_ankle_deflection: t = " << reference.time(k)
          << " s: no sole of the reference is on the ground";
      throw std::runtime_error(msg.str());
    }
    for (int foot = 0; foot < 2; ++foot) {
      if (share[foot] == 0.0)
        continue;
      const Eigen::Vector3d point = (support[0] && support[1]) ? centre[foot] + offset : zmp;
      const Eigen::Isometry3d& ankle_pose = ankles[k][foot];
      const Eigen::Vector3d force_local = ankle_pose.linear().transpose() * (share[foot] * force);
      const Eigen::Vector3d tau = ankle_pose.linear().transpose() *
                                  (point - ankle_pose.translation()).cross(share[foot] * force);
      const double u = force_local.z() / linear_stiffness;
      const double theta_p = tau.y() / angular_stiffness;
      const double theta_r = tau.x() / angular_stiffness;
      report.max_sag = std::max(report.max_sag, std::abs(u));
      report.max_pitch = std::max(report.max_pitch, std::abs(theta_p));
      report.max_roll = std::max(report.max_roll, std::abs(theta_r));
      report.max_moment = std::max(report.max_moment, tau.head<2>().norm());
      report.deflection.row(k).segment<3>(3 * foot) << u, theta_p, theta_r;
      // T' = T A^-1 S^-1 A: the sole target of the rigid leg.
      const Eigen::Isometry3d ankle_to_sole = ankle_pose.inverse() * soles[k][foot];
      Eigen::Isometry3d spring = Eigen::Isometry3d::Identity();
      spring.translate(Eigen::Vector3d(0.0, 0.0, u));
      spring.rotate(Eigen::AngleAxisd(theta_p, Eigen::Vector3d::UnitY()));
      spring.rotate(Eigen::AngleAxisd(theta_r, Eigen::Vector3d::UnitX()));
      const Eigen::Isometry3d target =
          soles[k][foot] * ankle_to_sole.inverse() * spring.inverse() * ankle_to_sole;
      LegAngles leg_q;
      try {
        solve_leg_ik(legs[foot], base_pose(reference, k), target, leg_q);
      } catch (const std::exception& e) {
        std::ostringstream msg;
        msg << "compensate_ankle_deflection: t = " << reference.time(k) << " s: " << e.what();
        throw std::runtime_error(msg.str());
      }
      reference.q.row(k).segment<6>(6 * foot) = leg_q.transpose();
    }
  }
  return report;
}

} // namespace plantar::walking
