// Humanoid: a HumanoidDescription (names from the scene) resolved on a multibody::Model. On
// HRP-2: the legs found from the foot links up to the base in hip -> ankle order, their columns,
// the sole frames and the posture; the errors for each wrong name or structure; sole frames
// added by placement (add_sole_frames), checked by forward kinematics.
#include "multibody/data.h"
#include "multibody/kinematics.h"
#include "multibody/urdf_loader.h"
#include "multibody/walking/humanoid.h"
#include "multibody/walking/leg_geometry.h"
#include "tests/multibody/walking/hrp2_humanoid.h"
#include "tests/multibody/walking/urdf_fk.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <functional>
#include <random>
#include <stdexcept>
#include <string>
#include <urdf_parser/urdf_parser.h>

namespace {

using namespace plantar::walking;
using plantar::multibody::Model;
using plantar::multibody::SE3;
using plantar::walking::testing::hrp2_description;
using plantar::walking::testing::hrp2_model;
using plantar::walking::testing::hrp2_urdf;

/// Expects Humanoid(model, description) to throw std::invalid_argument whose message contains
/// every string of @p needles; prints the message.
void expect_rejected(const Model& model, const HumanoidDescription& description,
                     const std::vector<std::string>& needles) {
  try {
    const Humanoid humanoid(model, description);
    ADD_FAILURE() << "accepted; expected an error naming '" << needles.front() << "'";
  } catch (const std::invalid_argument& e) {
    std::printf("rejected: %s\n", e.what());
    for (const std::string& needle : needles)
      EXPECT_NE(std::string(e.what()).find(needle), std::string::npos)
          << "'" << needle << "' not in: " << e.what();
  }
}

TEST(Humanoid, ResolvesHrp2) {
  const Model model = hrp2_model();
  const HumanoidDescription description = hrp2_description();
  const Humanoid humanoid(model, description);
  EXPECT_EQ(humanoid.base_body, model.body_id("BODY"));
  EXPECT_EQ(humanoid.base_body, 1); // the free-floating base
  // Controlled joints: the description's order (jrl-walkgen's), 30 joints.
  ASSERT_EQ(humanoid.n_joints(), 30);
  EXPECT_EQ(humanoid.joint_names, description.controlled_joints);
  for (int k = 0; k < humanoid.n_joints(); ++k)
    EXPECT_EQ(humanoid.joints[k], model.joint_id(description.controlled_joints[k]));
  // Legs: hip yaw first, ankle roll last, in their columns 0-5 and 6-11.
  const char* prefix[2] = {"RLEG", "LLEG"};
  const char* sole[2] = {"r_sole", "l_sole"};
  for (int side = 0; side < 2; ++side) {
    for (int k = 0; k < 6; ++k) {
      const std::string name = std::string(prefix[side]) + "_JOINT" + std::to_string(k);
      EXPECT_EQ(humanoid.leg_joints[side][k], model.joint_id(name)) << name;
      EXPECT_EQ(humanoid.leg_columns[side][k], 6 * side + k) << name;
    }
    EXPECT_EQ(humanoid.foot_frames[side], model.frame_id(std::string(prefix[side]) + "_LINK5"));
    EXPECT_EQ(humanoid.sole_frames[side], model.frame_id(sole[side]));
    EXPECT_EQ(model.frames[humanoid.sole_frames[side]].body, humanoid.leg_joints[side][5]);
  }
  // Posture: the half-sitting arms, everything else 0.
  const double deg = M_PI / 180.0;
  ASSERT_EQ(humanoid.posture.size(), 30);
  Eigen::VectorXd expected = Eigen::VectorXd::Zero(30);
  const double arm[7] = {15, -10, 0, -30, 0, 0, 10};
  for (int i = 0; i < 7; ++i) {
    expected[16 + i] = arm[i] * deg;                      // RARM_JOINTi
    expected[23 + i] = (i == 1 ? -arm[i] : arm[i]) * deg; // LARM_JOINTi
  }
  std::printf("posture (deg):");
  for (int k = 0; k < 30; ++k)
    std::printf(" %s %.0f%s", humanoid.joint_names[k].c_str(), humanoid.posture[k] / deg,
                k + 1 < 30 ? "," : "\n");
  EXPECT_EQ((humanoid.posture - expected).cwiseAbs().maxCoeff(), 0.0);
  // to_configuration writes each column into its joint's coordinate, nothing else.
  Eigen::VectorXd angles(30);
  for (int k = 0; k < 30; ++k)
    angles[k] = 0.01 * (k + 1);
  Eigen::VectorXd q = model.neutral_configuration();
  const Eigen::VectorXd neutral = q;
  humanoid.to_configuration(model, angles, q);
  for (int j = 1; j < model.n_bodies; ++j) {
    if (model.nq_joint[j] != 1)
      continue;
    const auto it = std::find(description.controlled_joints.begin(),
                              description.controlled_joints.end(), model.joint_names[j]);
    ASSERT_NE(it, description.controlled_joints.end()) << model.joint_names[j];
    EXPECT_EQ(q[model.idx_q[j]], angles[it - description.controlled_joints.begin()]);
  }
  EXPECT_EQ((q.head<7>() - neutral.head<7>()).cwiseAbs().maxCoeff(), 0.0); // base untouched
}

TEST(Humanoid, ColumnsFollowTheControlledJointOrder) {
  const Model model = hrp2_model();
  // Reversed order: the legs' columns move, the leg joints (model ids) do not.
  HumanoidDescription reversed = hrp2_description();
  std::reverse(reversed.controlled_joints.begin(), reversed.controlled_joints.end());
  const Humanoid humanoid(model, reversed);
  const Humanoid reference(model, hrp2_description());
  EXPECT_EQ(humanoid.leg_joints, reference.leg_joints);
  for (int side = 0; side < 2; ++side)
    for (int k = 0; k < 6; ++k) {
      EXPECT_EQ(humanoid.leg_columns[side][k], 29 - reference.leg_columns[side][k]);
      EXPECT_EQ(humanoid.joint_names[humanoid.leg_columns[side][k]],
                model.joint_names[humanoid.leg_joints[side][k]]);
    }
  for (int k = 0; k < 30; ++k)
    EXPECT_EQ(humanoid.posture[k], reference.posture[29 - k]) << humanoid.joint_names[k];

  // No list: every actuated 1-DoF joint in model order.
  HumanoidDescription all = hrp2_description();
  all.controlled_joints.clear();
  const Humanoid every(model, all);
  std::vector<int> expected;
  for (int j = 1; j < model.n_bodies; ++j)
    if (model.nq_joint[j] == 1 && model.actuated[model.idx_v[j]])
      expected.push_back(j);
  EXPECT_EQ(every.joints, expected);
  EXPECT_EQ(every.n_joints(), 30);
  for (int side = 0; side < 2; ++side)
    for (int k = 0; k < 6; ++k)
      EXPECT_EQ(every.joint_names[every.leg_columns[side][k]],
                model.joint_names[every.leg_joints[side][k]]);
  for (const auto& [name, value] : all.posture) {
    const auto it = std::find(every.joint_names.begin(), every.joint_names.end(), name);
    ASSERT_NE(it, every.joint_names.end()) << name;
    EXPECT_EQ(every.posture[it - every.joint_names.begin()], value) << name;
  }
}

TEST(Humanoid, ClearErrors) {
  const Model model = hrp2_model();
  const auto modified = [](const std::function<void(HumanoidDescription&)>& change) {
    HumanoidDescription d = hrp2_description();
    change(d);
    return d;
  };
  // Unknown names.
  expect_rejected(model, modified([](auto& d) { d.base_link = "WAIST"; }), {"base link", "WAIST"});
  expect_rejected(model, modified([](auto& d) { d.foot_links[0] = "R_FOOT"; }),
                  {"right foot link", "R_FOOT"});
  expect_rejected(model, modified([](auto& d) { d.foot_links[1] = "L_FOOT"; }),
                  {"left foot link", "L_FOOT"});
  expect_rejected(model, modified([](auto& d) { d.controlled_joints[20] = "RARM_JOINT9"; }),
                  {"RARM_JOINT9"});
  expect_rejected(model, modified([](auto& d) { d.sole_frames[0] = "r_sole_centre"; }),
                  {"right sole frame", "r_sole_centre"});
  expect_rejected(model, modified([](auto& d) { d.sole_frames[1] = "LLEG_SOLE"; }),
                  {"left sole frame", "LLEG_SOLE"});
  // A foot link whose chain from the base does not have 6 actuated joints: a hand (chest 2 +
  // arm 7 = 9), a knee link (4).
  expect_rejected(model, modified([](auto& d) { d.foot_links[0] = "RARM_LINK6"; }),
                  {"right foot link", "RARM_LINK6", "has 9", "6"});
  expect_rejected(model, modified([](auto& d) { d.foot_links[1] = "LLEG_LINK3"; }),
                  {"left foot link", "LLEG_LINK3", "has 4", "6"});
  // A foot link that is not below the base link.
  expect_rejected(model, modified([](auto& d) { d.base_link = "CHEST_LINK1"; }),
                  {"RLEG_LINK5", "not below", "CHEST_LINK1"});
  // The base link must be its body's root link (r_sole is merged into RLEG_LINK5's body).
  expect_rejected(model, modified([](auto& d) { d.base_link = "r_sole"; }),
                  {"base link", "r_sole", "RLEG_LINK5"});
  // A posture joint that is not controlled: chest left out of the list, or no such joint.
  expect_rejected(model, modified([](auto& d) {
                    d.controlled_joints.erase(d.controlled_joints.begin() + 12);
                    d.posture.emplace_back("CHEST_JOINT0", 0.1);
                  }),
                  {"posture", "CHEST_JOINT0", "not a controlled joint"});
  expect_rejected(model, modified([](auto& d) { d.posture.emplace_back("NECK_JOINT", 0.1); }),
                  {"posture", "NECK_JOINT"});
  // A leg joint that is not controlled, a joint listed twice.
  expect_rejected(
      model, modified([](auto& d) { d.controlled_joints.erase(d.controlled_joints.begin() + 3); }),
      {"RLEG_JOINT3", "right leg", "not a controlled joint"});
  expect_rejected(model, modified([](auto& d) { d.controlled_joints.push_back("HEAD_JOINT1"); }),
                  {"HEAD_JOINT1", "twice"});
}

TEST(Humanoid, AddSoleFramesPlacesThemOnTheFoot) {
  // Soles given by placement on the foot links instead of the URDF's r_sole / l_sole links.
  HumanoidDescription description = hrp2_description();
  description.sole_frames = {"", ""};
  const Eigen::Matrix3d tilt = (Eigen::AngleAxisd(0.2, Eigen::Vector3d::UnitZ()) *
                                Eigen::AngleAxisd(-0.1, Eigen::Vector3d::UnitY()))
                                   .toRotationMatrix();
  description.sole_placements = {
      SE3(tilt, Eigen::Vector3d(0.02, -0.01, -0.11)),
      SE3(Eigen::Matrix3d::Identity(), Eigen::Vector3d(0.0153, 0.0100, -0.105))};
  Model model = plantar::multibody::build_model_from_urdf(hrp2_urdf());
  const size_t n_frames = model.frames.size();
  add_sole_frames(model, description);
  ASSERT_EQ(model.frames.size(), n_frames + 2);
  EXPECT_EQ(placed_sole_frame_name(description, LegSide::right), "RLEG_LINK5_sole");
  EXPECT_EQ(placed_sole_frame_name(description, LegSide::left), "LLEG_LINK5_sole");
  const Humanoid humanoid(model, description);
  for (int side = 0; side < 2; ++side) {
    EXPECT_EQ(humanoid.sole_frames[side],
              model.frame_id(placed_sole_frame_name(description, leg_sides[side])));
    EXPECT_EQ(model.frames[humanoid.sole_frames[side]].body,
              model.frames[humanoid.foot_frames[side]].body);
  }

  // World pose by forward kinematics at random configurations: foot pose * placement, the foot
  // pose by plantar_multibody and by the URDF chain of urdf_fk.h.
  const urdf::ModelInterfaceSharedPtr urdf = urdf::parseURDFFile(hrp2_urdf());
  ASSERT_TRUE(urdf);
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> unit(-1.0, 1.0);
  plantar::multibody::Data data(model);
  double worst = 0.0, worst_urdf = 0.0;
  for (int sample = 0; sample < 20; ++sample) {
    Eigen::VectorXd q = model.neutral_configuration();
    q.head<3>() = Eigen::Vector3d(unit(rng), unit(rng), 1.0 + unit(rng));
    q.segment<4>(3) = Eigen::Vector4d(unit(rng), unit(rng), unit(rng), unit(rng)).normalized();
    std::map<std::string, double> named;
    for (int j : humanoid.joints) {
      q[model.idx_q[j]] = 0.5 * unit(rng);
      named[model.joint_names[j]] = q[model.idx_q[j]];
    }
    Eigen::Isometry3d base = Eigen::Isometry3d::Identity();
    base.translation() = q.head<3>();
    base.linear() = Eigen::Quaterniond(q[6], q[3], q[4], q[5]).toRotationMatrix();
    plantar::multibody::forward_kinematics(model, data, q);
    for (int side = 0; side < 2; ++side) {
      const SE3 sole = plantar::multibody::frame_placement(model, data, humanoid.sole_frames[side]);
      const SE3 expected =
          plantar::multibody::frame_placement(model, data, humanoid.foot_frames[side]) *
          description.sole_placements[side];
      worst = std::max({worst, (sole.rotation - expected.rotation).cwiseAbs().maxCoeff(),
                        (sole.translation - expected.translation).cwiseAbs().maxCoeff()});
      const SE3& placement = description.sole_placements[side];
      Eigen::Isometry3d placement_iso = Eigen::Isometry3d::Identity();
      placement_iso.linear() = placement.rotation;
      placement_iso.translation() = placement.translation;
      const Eigen::Isometry3d oracle =
          base * plantar::walking::testing::link_pose(*urdf, description.foot_links[side], named) *
          placement_iso;
      worst_urdf = std::max({worst_urdf, (sole.rotation - oracle.linear()).cwiseAbs().maxCoeff(),
                             (sole.translation - oracle.translation()).cwiseAbs().maxCoeff()});
    }
  }
  // The left placement equals the URDF's l_sole link: the same pose as that frame.
  Eigen::VectorXd q = model.neutral_configuration();
  for (int j : humanoid.joints)
    q[model.idx_q[j]] = 0.3;
  plantar::multibody::forward_kinematics(model, data, q);
  const SE3 placed = plantar::multibody::frame_placement(model, data, humanoid.sole_frames[1]);
  const SE3 link = plantar::multibody::frame_placement(model, data, model.frame_id("l_sole"));
  const double link_error = std::max((placed.rotation - link.rotation).cwiseAbs().maxCoeff(),
                                     (placed.translation - link.translation).cwiseAbs().maxCoeff());
  std::printf("placed sole frames vs foot pose * placement: %.2e (tol 1e-14), vs the URDF chain "
              "%.2e (tol 1e-12); left vs l_sole link %.2e (tol 1e-14)\n",
              worst, worst_urdf, link_error);
  EXPECT_LT(worst, 1e-14);
  EXPECT_LT(worst_urdf, 1e-12);
  EXPECT_LT(link_error, 1e-14);

  // The closed form reads the placed sole: the left one as the URDF link, the tilted right one
  // is not the closed form's structure (the sole must not be rotated).
  std::string reason;
  const std::optional<LegGeometry> left =
      analytic_leg_geometry(model, humanoid, LegSide::left, reason);
  ASSERT_TRUE(left.has_value()) << reason;
  EXPECT_LT((left->ankle_to_sole - Eigen::Vector3d(0.0153, 0.0100, -0.105)).norm(), 1e-15);
  EXPECT_FALSE(analytic_leg_geometry(model, humanoid, LegSide::right, reason).has_value());
  std::printf("tilted right sole: %s\n", reason.c_str());
  EXPECT_NE(reason.find("RLEG_LINK5_sole"), std::string::npos) << reason;

  // Errors: the frame already exists (added twice), an unknown foot link.
  try {
    add_sole_frames(model, description);
    ADD_FAILURE() << "a second RLEG_LINK5_sole was added";
  } catch (const std::invalid_argument& e) {
    std::printf("rejected: %s\n", e.what());
    EXPECT_NE(std::string(e.what()).find("RLEG_LINK5_sole"), std::string::npos) << e.what();
  }
  HumanoidDescription unknown = description;
  unknown.foot_links[1] = "L_FOOT";
  Model fresh = plantar::multibody::build_model_from_urdf(hrp2_urdf());
  try {
    add_sole_frames(fresh, unknown);
    ADD_FAILURE() << "unknown foot link accepted";
  } catch (const std::invalid_argument& e) {
    std::printf("rejected: %s\n", e.what());
    EXPECT_NE(std::string(e.what()).find("L_FOOT"), std::string::npos) << e.what();
  }
  // Soles named in the description: nothing is added.
  Model named = plantar::multibody::build_model_from_urdf(hrp2_urdf());
  const size_t n_named = named.frames.size();
  add_sole_frames(named, hrp2_description());
  EXPECT_EQ(named.frames.size(), n_named);
}

} // namespace
