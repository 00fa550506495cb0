#include "multibody/walking/ankle_compensation.h"

#include "multibody/kinematics.h"
#include "multibody/walking/leg_solver.h"

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

Eigen::Isometry3d base_pose(const JointReference& reference, int k) {
  Eigen::Isometry3d base = Eigen::Isometry3d::Identity();
  const auto& o = reference.base_orientation;
  base.linear() = Eigen::Quaterniond(o(k, 0), o(k, 1), o(k, 2), o(k, 3)).toRotationMatrix();
  base.translation() = reference.base_position.row(k).transpose();
  return base;
}

Eigen::Isometry3d to_isometry(const multibody::SE3& pose) {
  Eigen::Isometry3d result = Eigen::Isometry3d::Identity();
  result.linear() = pose.rotation;
  result.translation() = pose.translation;
  return result;
}

} // namespace

AnkleCompensationReport compensate_ankle_deflection(const multibody::Model& model,
                                                    const Humanoid& humanoid,
                                                    const Eigen::Vector3d& compliance_centre,
                                                    double angular_stiffness,
                                                    double linear_stiffness,
                                                    JointReference& reference, LegIkMethod leg_ik) {
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
  if (!model.has_free_base() || humanoid.base_body != 1 ||
      reference.q.cols() != humanoid.n_joints())
    throw std::invalid_argument("compensate_ankle_deflection: the model needs a free base at "
                                "the base link and the reference the humanoid's joints");
  multibody::Data data(model);
  const int nb = model.n_bodies;
  std::array<LegSolver, 2> legs = {LegSolver(model, humanoid, LegSide::right, leg_ik),
                                   LegSolver(model, humanoid, LegSide::left, leg_ik)};
  const multibody::SE3 centre(Eigen::Matrix3d::Identity(), compliance_centre);

  // Body CoM positions (3 x bodies per sample), sole and ankle poses, from the original q.
  std::vector<Eigen::Matrix3Xd> points(n, Eigen::Matrix3Xd::Zero(3, nb));
  std::vector<std::array<Eigen::Isometry3d, 2>> soles(n), ankles(n);
  Eigen::VectorXd q = model.neutral_configuration();
  for (int k = 0; k < n; ++k) {
    q.head<3>() = reference.base_position.row(k).transpose();
    q.segment<4>(3) << reference.base_orientation(k, 1), reference.base_orientation(k, 2),
        reference.base_orientation(k, 3), reference.base_orientation(k, 0);
    humanoid.to_configuration(model, reference.q.row(k).transpose(), q);
    multibody::forward_kinematics(model, data, q);
    for (int i = 1; i < nb; ++i)
      points[k].col(i) = data.oMi[i].act_point(model.inertia[i].com);
    for (int foot = 0; foot < 2; ++foot) {
      soles[k][foot] =
          to_isometry(multibody::frame_placement(model, data, humanoid.sole_frames[foot]));
      ankles[k][foot] =
          to_isometry(multibody::frame_placement(model, data, humanoid.foot_frames[foot]) * centre);
    }
  }

  const double T = reference.period;
  const Eigen::Vector3d g(0.0, 0.0, -9.81);
  AnkleCompensationReport report;
  report.deflection = Eigen::Matrix<double, Eigen::Dynamic, 6>::Zero(n, 6);
  for (int k = 0; k < n; ++k) {
    const int k0 = std::clamp(k, 1, n - 2); // one-sided at the ends (standing samples)
    Eigen::Vector3d force = Eigen::Vector3d::Zero(), moment = Eigen::Vector3d::Zero();
    for (int i = 1; i < nb; ++i) {
      const double m = model.inertia[i].mass;
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
          report.max_force_mismatch, (force - model.total_mass() * (com_acceleration - g)).norm());
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
      // On the ground when at its planned ground height (0 on flat references).
      const double ground = reference.ground.rows() > k ? reference.ground(k, foot) : 0.0;
      support[foot] = centre[foot].z() - ground < 1e-6;
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
      for (int j = 0; j < 6; ++j)
        leg_q[j] = reference.q(k, humanoid.leg_columns[foot][j]);
      try {
        legs[foot].solve(base_pose(reference, k), target, leg_q);
      } catch (const std::exception& e) {
        std::ostringstream msg;
        msg << "compensate_ankle_deflection: t = " << reference.time(k) << " s: " << e.what();
        throw std::runtime_error(msg.str());
      }
      for (int j = 0; j < 6; ++j)
        reference.q(k, humanoid.leg_columns[foot][j]) = leg_q[j];
    }
  }
  return report;
}

} // namespace plantar::walking
