// Analytic leg IK against forward kinematics composed from the URDF joint transforms that
// urdfdom parsed (tests/multibody/walking/urdf_fk.h), not from plantar_walking's own FK.
#include "multibody/walking/leg_ik.h"
#include "tests/multibody/walking/urdf_fk.h"

#include <cstdio>
#include <gtest/gtest.h>
#include <random>
#include <stdexcept>

namespace {

using namespace plantar::walking;
using plantar::walking::testing::link_pose;

const std::string kUrdf = std::string(PLANTAR_SOURCE_DIR) + "/models/hrp2/hrp2.urdf";

TEST(LegGeometry, ReadFromUrdf) {
  const auto model = load_urdf(kUrdf);
  for (LegSide side : {LegSide::right, LegSide::left}) {
    const LegGeometry leg = read_leg_geometry(*model, side);
    const double s = side == LegSide::right ? -1.0 : 1.0;
    std::printf("%s leg: hip (%.4f, %.4f, %.4f), d = %.4f, L1 = %.4f, L2 = %.4f, sole "
                "(%.4f, %.4f, %.4f)\n",
                side == LegSide::right ? "right" : "left", leg.hip_offset.x(), leg.hip_offset.y(),
                leg.hip_offset.z(), leg.thigh_lateral_offset, leg.thigh_length, leg.shank_length,
                leg.ankle_to_sole.x(), leg.ankle_to_sole.y(), leg.ankle_to_sole.z());
    // Public HRP-2 numbers (hrp2.md).
    EXPECT_NEAR(leg.hip_offset.y(), s * 0.06, 1e-12);
    EXPECT_NEAR(leg.thigh_lateral_offset, s * 0.035, 1e-12);
    EXPECT_NEAR(leg.thigh_length, 0.30, 1e-12);
    EXPECT_NEAR(leg.shank_length, 0.30, 1e-12);
    EXPECT_NEAR(leg.ankle_to_sole.z(), -0.105, 1e-12);
  }
}

TEST(LegGeometry, RejectsWrongStructure) {
  const auto model = load_urdf(kUrdf);
  // Break the chain: a knee axis along x.
  model->joints_.at("RLEG_JOINT3")->axis = urdf::Vector3(1, 0, 0);
  EXPECT_THROW(read_leg_geometry(*model, LegSide::right), std::runtime_error);
  EXPECT_NO_THROW(read_leg_geometry(*model, LegSide::left));
  EXPECT_THROW(load_urdf("/nonexistent/robot.urdf"), std::runtime_error);
}

TEST(LegIk, RoundTripWithUrdfForwardKinematics) {
  const auto model = load_urdf(kUrdf);
  std::mt19937 rng(20081201);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  double max_position_error = 0.0, max_rotation_error = 0.0, max_angle_error = 0.0;
  double max_self_fk_error = 0.0;
  int n_samples = 0, n_other_branch = 0;
  for (LegSide side : {LegSide::right, LegSide::left}) {
    const LegGeometry leg = read_leg_geometry(*model, side);
    for (int sample = 0; sample < 2000; ++sample) {
      // Random angles inside the limits, knee >= 0.05 rad (the closed form picks the
      // forward-bending branch; at q3 = 0 the ankle pitch/hip pitch split is singular).
      LegAngles q;
      for (int i = 0; i < 6; ++i)
        q(i) = leg.lower_limit(i) + unit(rng) * (leg.upper_limit(i) - leg.lower_limit(i));
      q(3) = std::max(q(3), 0.05);
      // Random body pose.
      Eigen::Isometry3d body = Eigen::Isometry3d::Identity();
      body.translation() = Eigen::Vector3d(unit(rng) - 0.5, unit(rng) - 0.5, 0.5 + unit(rng));
      body.linear() = Eigen::Quaterniond(Eigen::Vector4d::Random().normalized()).toRotationMatrix();
      std::map<std::string, double> named;
      for (int i = 0; i < 6; ++i)
        named[leg.joint_names[i]] = q(i);
      // The IK returns the branch with the hip above the ankle along the ankle-pitch link's z
      // axis (beta >= 0, every standing posture); skip the deep-squat poses of the other branch.
      const std::string prefix = side == LegSide::right ? "RLEG" : "LLEG";
      const Eigen::Isometry3d ankle_pitch_link = link_pose(*model, prefix + "_LINK4", named);
      const Eigen::Vector3d hip = link_pose(*model, prefix + "_LINK1", named).translation();
      if ((ankle_pitch_link.inverse() * hip).z() < 1e-3) {
        ++n_other_branch;
        continue;
      }
      const Eigen::Isometry3d sole = body * link_pose(*model, leg.sole_link, named);
      LegAngles solved;
      solve_leg_ik(leg, body, sole, solved);
      for (int i = 0; i < 6; ++i)
        named[leg.joint_names[i]] = solved(i);
      const Eigen::Isometry3d reached = body * link_pose(*model, leg.sole_link, named);
      max_position_error =
          std::max(max_position_error, (reached.translation() - sole.translation()).norm());
      max_rotation_error =
          std::max(max_rotation_error,
                   Eigen::AngleAxisd(reached.linear().transpose() * sole.linear()).angle());
      max_angle_error = std::max(max_angle_error, (solved - q).cwiseAbs().maxCoeff());
      max_self_fk_error = std::max(
          max_self_fk_error,
          (leg_forward_kinematics(leg, body, q).matrix() - sole.matrix()).cwiseAbs().maxCoeff());
      ++n_samples;
    }
  }
  std::printf("skipped %d poses of the beta < 0 branch\n", n_other_branch);
  std::printf("%d random poses: sole position error %.3e m, orientation error %.3e rad, joint "
              "angle error %.3e rad (tol 1e-9 each); library FK vs URDF FK %.3e\n",
              n_samples, max_position_error, max_rotation_error, max_angle_error,
              max_self_fk_error);
  EXPECT_LT(max_position_error, 1e-9);
  EXPECT_LT(max_rotation_error, 1e-9);
  EXPECT_LT(max_angle_error, 1e-9);
  EXPECT_LT(max_self_fk_error, 1e-12);
}

TEST(LegIk, OutOfReachThrowsAndNoAllocation) {
  const auto model = load_urdf(kUrdf);
  const LegGeometry leg = read_leg_geometry(*model, LegSide::right);
  Eigen::Isometry3d body = Eigen::Isometry3d::Identity();
  Eigen::Isometry3d sole = Eigen::Isometry3d::Identity();
  sole.translation() = Eigen::Vector3d(0.0, -0.105, -0.8); // 0.695 m below the hip: > L1 + L2
  LegAngles q;
  EXPECT_THROW(solve_leg_ik(leg, body, sole, q), std::runtime_error);
  // Straight leg exactly at full extension is reachable: all angles zero.
  sole.translation() = leg_forward_kinematics(leg, body, LegAngles::Zero()).translation();
  solve_leg_ik(leg, body, sole, q);
  std::printf("straight leg: max |q| = %.3e rad (tol 1e-6; sqrt of round-off at the "
              "singular full extension)\n",
              q.cwiseAbs().maxCoeff());
  EXPECT_LT(q.cwiseAbs().maxCoeff(), 1e-6);
}

} // namespace
