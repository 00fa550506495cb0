// Analytic leg IK against forward kinematics composed from the URDF joint transforms that
// urdfdom parsed (tests/multibody/walking/urdf_fk.h), not from plantar_walking's own FK nor
// plantar_multibody's.
#include "multibody/walking/leg_ik.h"
#include "multibody/walking/leg_solver.h"
#include "tests/multibody/walking/hrp2_humanoid.h"
#include "tests/multibody/walking/urdf_fk.h"

#include <cstdio>
#include <gtest/gtest.h>
#include <random>
#include <stdexcept>
#include <urdf_parser/urdf_parser.h>

namespace {

using namespace plantar::walking;
using plantar::walking::testing::hrp2_description;
using plantar::walking::testing::hrp2_model;
using plantar::walking::testing::hrp2_urdf;
using plantar::walking::testing::link_pose;

urdf::ModelInterfaceSharedPtr parse_hrp2() {
  urdf::ModelInterfaceSharedPtr model = urdf::parseURDFFile(hrp2_urdf());
  if (!model)
    throw std::runtime_error("urdfdom failed to parse " + hrp2_urdf());
  return model;
}

/// URDF child link of a joint (urdfdom's view, not the Model's).
std::string child_link(const urdf::ModelInterface& urdf, const std::string& joint) {
  return urdf.getJoint(joint)->child_link_name;
}

TEST(LegGeometry, ReadFromModel) {
  const plantar::multibody::Model model = hrp2_model();
  const Humanoid humanoid(model, hrp2_description());
  for (LegSide side : leg_sides) {
    const LegGeometry leg = read_leg_geometry(model, humanoid, side);
    const double s = side == LegSide::right ? -1.0 : 1.0;
    std::printf("%s leg: hip (%.4f, %.4f, %.4f), d = %.4f, L1 = %.4f, L2 = %.4f, sole "
                "(%.4f, %.4f, %.4f)\n",
                to_string(side), leg.hip_offset.x(), leg.hip_offset.y(), leg.hip_offset.z(),
                leg.thigh_lateral_offset, leg.thigh_length, leg.shank_length, leg.ankle_to_sole.x(),
                leg.ankle_to_sole.y(), leg.ankle_to_sole.z());
    // Public HRP-2 numbers (hrp2.md).
    EXPECT_EQ(leg.side, side);
    EXPECT_NEAR(leg.hip_offset.y(), s * 0.06, 1e-12);
    EXPECT_NEAR(leg.thigh_lateral_offset, s * 0.035, 1e-12);
    EXPECT_NEAR(leg.thigh_length, 0.30, 1e-12);
    EXPECT_NEAR(leg.shank_length, 0.30, 1e-12);
    EXPECT_NEAR(leg.ankle_to_sole.z(), -0.105, 1e-12);
    const std::string prefix = side == LegSide::right ? "RLEG" : "LLEG";
    for (int i = 0; i < 6; ++i)
      EXPECT_EQ(leg.joint_names[i], prefix + "_JOINT" + std::to_string(i));
  }
}

TEST(LegGeometry, RejectsWrongStructure) {
  plantar::multibody::Model model = hrp2_model();
  const Humanoid humanoid(model, hrp2_description());
  // Break the chain: a knee axis along x.
  const int knee = model.joint_id("RLEG_JOINT3");
  ASSERT_EQ(humanoid.leg_joints[0][3], knee);
  model.joint_axis[knee] = Eigen::Vector3d::UnitX();
  std::string reason;
  const std::optional<LegGeometry> right =
      analytic_leg_geometry(model, humanoid, LegSide::right, reason);
  std::printf("knee axis along x: %s\n", reason.c_str());
  EXPECT_FALSE(right.has_value());
  EXPECT_NE(reason.find("RLEG_JOINT3"), std::string::npos) << reason;
  EXPECT_NE(reason.find("axis"), std::string::npos) << reason;
  try {
    read_leg_geometry(model, humanoid, LegSide::right);
    ADD_FAILURE() << "read_leg_geometry accepted a knee axis along x";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("right leg"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("RLEG_JOINT3"), std::string::npos) << e.what();
  }
  // The other leg is untouched.
  reason.clear();
  EXPECT_TRUE(analytic_leg_geometry(model, humanoid, LegSide::left, reason).has_value()) << reason;
  EXPECT_NO_THROW(read_leg_geometry(model, humanoid, LegSide::left));
  // The leg solver falls back to the numerical IK and says why.
  const LegSolver solver(model, humanoid, LegSide::right);
  EXPECT_FALSE(solver.analytic());
  EXPECT_NE(solver.why_numerical().find("RLEG_JOINT3"), std::string::npos)
      << solver.why_numerical();
  EXPECT_TRUE(LegSolver(model, humanoid, LegSide::left).analytic());
}

TEST(LegIk, RoundTripWithUrdfForwardKinematics) {
  const plantar::multibody::Model model = hrp2_model();
  const HumanoidDescription description = hrp2_description();
  const Humanoid humanoid(model, description);
  const auto urdf = parse_hrp2();
  std::mt19937 rng(20081201);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  double max_position_error = 0.0, max_rotation_error = 0.0, max_angle_error = 0.0;
  double max_self_fk_error = 0.0;
  int n_samples = 0, n_other_branch = 0;
  for (LegSide side : leg_sides) {
    const LegGeometry leg = read_leg_geometry(model, humanoid, side);
    const std::string& sole_link = description.sole_frames[static_cast<int>(side)];
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
      const Eigen::Isometry3d ankle_pitch_link =
          link_pose(*urdf, child_link(*urdf, leg.joint_names[4]), named);
      const Eigen::Vector3d hip =
          link_pose(*urdf, child_link(*urdf, leg.joint_names[1]), named).translation();
      if ((ankle_pitch_link.inverse() * hip).z() < 1e-3) {
        ++n_other_branch;
        continue;
      }
      const Eigen::Isometry3d sole = body * link_pose(*urdf, sole_link, named);
      LegAngles solved;
      solve_leg_ik(leg, body, sole, solved);
      for (int i = 0; i < 6; ++i)
        named[leg.joint_names[i]] = solved(i);
      const Eigen::Isometry3d reached = body * link_pose(*urdf, sole_link, named);
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
  EXPECT_GT(n_samples, 3000);
  EXPECT_LT(max_position_error, 1e-9);
  EXPECT_LT(max_rotation_error, 1e-9);
  EXPECT_LT(max_angle_error, 1e-9);
  EXPECT_LT(max_self_fk_error, 1e-12);
}

// LegSolver: the closed form on HRP-2, and the numerical solver asked for explicitly, both
// against the URDF chain, from a warm start 0.1 rad away from the solution.
TEST(LegSolver, ClosedFormAndNumericalAgreeWithUrdf) {
  const plantar::multibody::Model model = hrp2_model();
  const HumanoidDescription description = hrp2_description();
  const Humanoid humanoid(model, description);
  const auto urdf = parse_hrp2();
  std::mt19937 rng(20240601);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  double worst[2] = {0.0, 0.0}; // max sole error (m + rad) per method
  double worst_angle = 0.0;     // numerical vs closed form
  for (LegSide side : leg_sides) {
    LegSolver analytic(model, humanoid, side);
    LegSolver numerical(model, humanoid, side, LegIkMethod::numerical);
    ASSERT_TRUE(analytic.analytic());
    ASSERT_FALSE(numerical.analytic());
    std::printf("%s leg: numerical because '%s'\n", to_string(side),
                numerical.why_numerical().c_str());
    const LegGeometry leg = read_leg_geometry(model, humanoid, side);
    const std::string& sole_link = description.sole_frames[static_cast<int>(side)];
    for (int sample = 0; sample < 50; ++sample) {
      // Walking-like angles: hip yaw/roll small, knee well bent.
      LegAngles q;
      q << 0.3 * (unit(rng) - 0.5), 0.2 * (unit(rng) - 0.5), -0.2 - 0.4 * unit(rng),
          0.4 + 0.6 * unit(rng), -0.2 - 0.4 * unit(rng), 0.2 * (unit(rng) - 0.5);
      Eigen::Isometry3d body = Eigen::Isometry3d::Identity();
      body.translation() = Eigen::Vector3d(unit(rng) - 0.5, unit(rng) - 0.5, 0.5 + unit(rng));
      body.linear() =
          Eigen::AngleAxisd(0.4 * (unit(rng) - 0.5), Eigen::Vector3d::UnitZ()).toRotationMatrix();
      std::map<std::string, double> named;
      for (int i = 0; i < 6; ++i)
        named[leg.joint_names[i]] = q(i);
      const Eigen::Isometry3d sole = body * link_pose(*urdf, sole_link, named);
      LegAngles solutions[2];
      LegSolver* solvers[2] = {&analytic, &numerical};
      for (int m = 0; m < 2; ++m) {
        solutions[m] = q + LegAngles::Constant(0.1); // warm start (unused by the closed form)
        solvers[m]->solve(body, sole, solutions[m]);
        for (int i = 0; i < 6; ++i)
          named[leg.joint_names[i]] = solutions[m](i);
        const Eigen::Isometry3d reached = body * link_pose(*urdf, sole_link, named);
        worst[m] = std::max(
            worst[m], (reached.translation() - sole.translation()).norm() +
                          Eigen::AngleAxisd(reached.linear().transpose() * sole.linear()).angle());
        // sole_pose() is the solver's own FK.
        worst[m] =
            std::max(worst[m], (solvers[m]->sole_pose(body, solutions[m]).matrix() - sole.matrix())
                                   .cwiseAbs()
                                   .maxCoeff());
      }
      worst_angle = std::max(worst_angle, (solutions[1] - solutions[0]).cwiseAbs().maxCoeff());
    }
  }
  std::printf("LegSolver vs URDF chain: closed form %.2e, numerical %.2e (m + rad, tol 1e-9); "
              "numerical vs closed-form angles %.2e rad (tol 1e-8)\n",
              worst[0], worst[1], worst_angle);
  EXPECT_LT(worst[0], 1e-9);
  EXPECT_LT(worst[1], 1e-9);
  EXPECT_LT(worst_angle, 1e-8);
}

TEST(LegIk, OutOfReachThrowsAndNoAllocation) {
  const plantar::multibody::Model model = hrp2_model();
  const Humanoid humanoid(model, hrp2_description());
  const LegGeometry leg = read_leg_geometry(model, humanoid, LegSide::right);
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
