// models/hrp2/hrp2.urdf parses with urdfdom and has the public HRP-2 numbers
// of /work/shared/reference/hrp2.md.
#include "tests/multibody/walking/urdf_fk.h"

#include <cmath>
#include <cstdio>
#include <gtest/gtest.h>
#include <urdf_parser/urdf_parser.h>

namespace {

using plantar::walking::testing::link_pose;
using plantar::walking::testing::mass_and_com;

const std::string kUrdf = std::string(PLANTAR_SOURCE_DIR) + "/models/hrp2/hrp2.urdf";

std::vector<std::string> expected_joint_names() {
  std::vector<std::string> names;
  for (const char* leg : {"RLEG", "LLEG"})
    for (int i = 0; i < 6; ++i)
      names.push_back(std::string(leg) + "_JOINT" + std::to_string(i));
  for (const char* part : {"CHEST", "HEAD"})
    for (int i = 0; i < 2; ++i)
      names.push_back(std::string(part) + "_JOINT" + std::to_string(i));
  for (const char* arm : {"RARM", "LARM"})
    for (int i = 0; i < 7; ++i)
      names.push_back(std::string(arm) + "_JOINT" + std::to_string(i));
  return names;
}

std::map<std::string, double> half_sitting_legs() {
  const double deg = M_PI / 180.0;
  std::map<std::string, double> q;
  for (const char* leg : {"RLEG", "LLEG"}) {
    q[std::string(leg) + "_JOINT2"] = -26 * deg;
    q[std::string(leg) + "_JOINT3"] = 50 * deg;
    q[std::string(leg) + "_JOINT4"] = -24 * deg;
  }
  return q;
}

TEST(Hrp2Urdf, ThirtyNamedRevoluteJointsWithLimits) {
  const urdf::ModelInterfaceSharedPtr model = urdf::parseURDFFile(kUrdf);
  ASSERT_TRUE(model) << "urdfdom failed to parse " << kUrdf;
  EXPECT_EQ(model->getRoot()->name, "BODY");
  int n_revolute = 0;
  for (const auto& [name, joint] : model->joints_) {
    if (joint->type == urdf::Joint::FIXED)
      continue;
    ++n_revolute;
    EXPECT_EQ(joint->type, urdf::Joint::REVOLUTE) << name;
  }
  std::printf("revolute joints: %d (expected 30), links: %zu\n", n_revolute, model->links_.size());
  EXPECT_EQ(n_revolute, 30);
  for (const std::string& name : expected_joint_names()) {
    const urdf::JointConstSharedPtr joint = model->getJoint(name);
    ASSERT_TRUE(joint) << "missing joint " << name;
    ASSERT_TRUE(joint->limits) << name;
    EXPECT_LT(joint->limits->lower, 0.0) << name;
    EXPECT_GE(joint->limits->upper, 0.0) << name;
    EXPECT_GT(joint->limits->effort, 0.0) << name;
    EXPECT_GT(joint->limits->velocity, 0.0) << name;
  }
  // Leg axes in HRP-2 order: yaw, roll, pitch, pitch, pitch, roll.
  const int axis_index[6] = {2, 0, 1, 1, 1, 0};
  for (const char* leg : {"RLEG", "LLEG"})
    for (int i = 0; i < 6; ++i) {
      const auto& axis = model->getJoint(std::string(leg) + "_JOINT" + std::to_string(i))->axis;
      const double component[3] = {axis.x, axis.y, axis.z};
      EXPECT_DOUBLE_EQ(component[axis_index[i]], 1.0) << leg << i;
    }
  for (const char* sole : {"r_sole", "l_sole"})
    EXPECT_TRUE(model->getLink(sole)) << sole;
}

TEST(Hrp2Urdf, MassAndCentreOfMassHeight) {
  const urdf::ModelInterfaceSharedPtr model = urdf::parseURDFFile(kUrdf);
  ASSERT_TRUE(model);
  for (const auto& [name, link] : model->links_) {
    if (!link->inertial)
      continue;
    const auto& in = *link->inertial;
    EXPECT_GT(in.mass, 0.0) << name;
    // principal moments of a real body satisfy the triangle inequality
    EXPECT_LE(in.ixx, in.iyy + in.izz) << name;
    EXPECT_LE(in.iyy, in.ixx + in.izz) << name;
    EXPECT_LE(in.izz, in.ixx + in.iyy) << name;
  }
  // Standing on flat ground: the sole frames at z = 0, so CoM height = com.z - sole.z.
  const std::map<std::string, double> straight;
  const auto [mass, com_straight] = mass_and_com(*model, straight);
  const double sole_straight = link_pose(*model, "r_sole", straight).translation().z();
  const auto q_bent = half_sitting_legs();
  const auto [mass_bent, com_bent] = mass_and_com(*model, q_bent);
  const double sole_bent = link_pose(*model, "r_sole", q_bent).translation().z();
  const double h_straight = com_straight.z() - sole_straight;
  const double h_bent = com_bent.z() - sole_bent;
  std::printf("total mass %.4f kg (public 58, tolerance 0.5)\n", mass);
  std::printf("CoM height, straight legs: %.4f m (waist %.4f m)\n", h_straight, -sole_straight);
  std::printf("CoM height, half-sitting legs (-26, 50, -24 deg): %.4f m (public walking 0.814, "
              "tolerance 0.01), waist %.4f m, CoM x %.4f m ahead of the ankle\n",
              h_bent, -sole_bent,
              com_bent.x() - link_pose(*model, "RLEG_LINK5", q_bent).translation().x());
  EXPECT_NEAR(mass, 58.0, 0.5);
  EXPECT_NEAR(h_bent, 0.814, 0.01);
  EXPECT_GT(h_straight, h_bent);
  // Laterally symmetric.
  EXPECT_NEAR(com_straight.y(), 0.0, 1e-12);
}

TEST(Hrp2Urdf, LegAndArmLengths) {
  const urdf::ModelInterfaceSharedPtr model = urdf::parseURDFFile(kUrdf);
  ASSERT_TRUE(model);
  const std::map<std::string, double> zero;
  for (const char* leg : {"RLEG", "LLEG"}) {
    const std::string p(leg);
    const double side = p == "RLEG" ? -1.0 : 1.0;
    const Eigen::Vector3d hip = link_pose(*model, p + "_LINK2", zero).translation();
    const Eigen::Vector3d knee = link_pose(*model, p + "_LINK3", zero).translation();
    const Eigen::Vector3d ankle = link_pose(*model, p + "_LINK5", zero).translation();
    const Eigen::Vector3d sole =
        link_pose(*model, side < 0 ? "r_sole" : "l_sole", zero).translation();
    std::printf("%s: hip (%.4f, %.4f, %.4f), thigh %.4f m, shank %.4f m, ankle height %.4f m, "
                "sole centre - ankle (%.4f, %.4f) m\n",
                leg, hip.x(), hip.y(), hip.z(), hip.z() - knee.z(), knee.z() - ankle.z(),
                ankle.z() - sole.z(), sole.x() - ankle.x(), sole.y() - ankle.y());
    EXPECT_NEAR(hip.y(), side * 0.06, 1e-12);             // public: waist to hip 0.06 m
    EXPECT_NEAR(ankle.y(), side * (0.06 + 0.035), 1e-12); // public: + hip offset 0.035 m
    EXPECT_NEAR(hip.z() - knee.z(), 0.30, 1e-12);         // public: thigh
    EXPECT_NEAR(knee.z() - ankle.z(), 0.30, 1e-12);       // public: shank
    EXPECT_NEAR(ankle.z() - sole.z(), 0.105, 1e-12);      // public: ankle height
    // public: ankle at (0.0933, 0.059) from the rear inner corner of a 0.2172 x 0.138 sole
    EXPECT_NEAR(sole.x() - ankle.x(), 0.2172 / 2 - 0.0933, 1e-12);
    EXPECT_NEAR(side * (sole.y() - ankle.y()), 0.138 / 2 - 0.059, 1e-12);
  }
  for (const char* arm : {"RARM", "LARM"}) {
    const std::string p(arm);
    const Eigen::Vector3d shoulder = link_pose(*model, p + "_LINK0", zero).translation();
    const Eigen::Vector3d elbow = link_pose(*model, p + "_LINK3", zero).translation();
    const Eigen::Vector3d wrist = link_pose(*model, p + "_LINK5", zero).translation();
    std::printf("%s: upper arm %.4f m, forearm %.4f m\n", arm, (shoulder - elbow).norm(),
                (elbow - wrist).norm());
    EXPECT_NEAR((shoulder - elbow).norm(), 0.25, 1e-12);
    EXPECT_NEAR((elbow - wrist).norm(), 0.25, 1e-12);
  }
}

} // namespace
