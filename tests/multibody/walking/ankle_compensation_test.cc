// Feed-forward compensation of the compliant-ankle deflection: the standing posture against
// the closed form (each foot carries M g / 2 at its sole centre), and the six-step walk: the
// ground force against M (c'' - g) of the reference's CoM column, and the deflected feet,
// recomposed by the test's own URDF chain, on their planned poses; the compliance centre
// at the ankle joint point and off it.
#include "multibody/walking/ankle_compensation.h"
#include "multibody/walking/walking_reference.h"
#include "tests/multibody/walking/hrp2_humanoid.h"
#include "tests/multibody/walking/urdf_fk.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <map>
#include <stdexcept>
#include <urdf_parser/urdf_parser.h>
#include <vector>

namespace {

using namespace plantar::walking;
using plantar::walking::testing::hrp2_description;
using plantar::walking::testing::hrp2_model;
using plantar::walking::testing::hrp2_urdf;
using plantar::walking::testing::link_pose;

const Footstep kRightSole{0.0, -0.105, 0.0}, kLeftSole{0.0, 0.105, 0.0};

urdf::ModelInterfaceSharedPtr parse_hrp2() {
  urdf::ModelInterfaceSharedPtr model = urdf::parseURDFFile(hrp2_urdf());
  if (!model)
    throw std::runtime_error("urdfdom failed to parse " + hrp2_urdf());
  return model;
}

std::map<std::string, double> named_angles(const JointReference& ref, int k) {
  std::map<std::string, double> named;
  for (int i = 0; i < ref.q.cols(); ++i)
    named[ref.joint_names[i]] = ref.q(k, i);
  return named;
}

/// Largest distance (m) and rotation angle (rad), over both feet, between the planned foot
/// (foot link with the original q) and the compensated foot (foot link with the compensated q,
/// then the deflected spring at the compliance centre c: Trans(c) Trans(0, 0, u) Ry(theta_p)
/// Rx(theta_r) Trans(-c)), by the test's own URDF chain.
std::pair<double, double> foot_pose_error(const urdf::ModelInterface& model,
                                          const JointReference& planned,
                                          const JointReference& compensated,
                                          const Eigen::Matrix<double, Eigen::Dynamic, 6>& theta,
                                          const Eigen::Vector3d& centre, int k) {
  double distance = 0.0, angle = 0.0;
  const auto links = hrp2_description().foot_links;
  for (int foot = 0; foot < 2; ++foot) {
    const Eigen::Isometry3d before = link_pose(model, links[foot], named_angles(planned, k));
    Eigen::Isometry3d spring = Eigen::Isometry3d::Identity();
    spring.translate(centre);
    spring.translate(Eigen::Vector3d(0, 0, theta(k, 3 * foot)));
    spring.rotate(Eigen::AngleAxisd(theta(k, 3 * foot + 1), Eigen::Vector3d::UnitY()));
    spring.rotate(Eigen::AngleAxisd(theta(k, 3 * foot + 2), Eigen::Vector3d::UnitX()));
    spring.translate(-centre);
    const Eigen::Isometry3d after =
        link_pose(model, links[foot], named_angles(compensated, k)) * spring;
    distance = std::max(distance, (before.translation() - after.translation()).norm());
    angle =
        std::max(angle, Eigen::AngleAxisd(before.linear().transpose() * after.linear()).angle());
  }
  return {distance, angle};
}

/// Standing: each sole carries M g / 2 at its centre s = (0.0153, -+0.0100, -0.105) m in the
/// foot link frame (docs/hrp2_model.md), the foot frame parallel to the world; with the
/// compliance centre c the moment arm is s - c: u = M g / (2 k_z), theta_r = (s - c)_y M g /
/// (2 k), theta_p = -(s - c)_x M g / (2 k).
void check_standing(const Eigen::Vector3d& centre) {
  const plantar::multibody::Model model = hrp2_model();
  const Humanoid humanoid(model, hrp2_description());
  const auto urdf = parse_hrp2();
  const JointReference planned =
      make_standing_reference(model, humanoid, 1.0, kRightSole, kLeftSole);
  JointReference ref = planned;
  const double k = 600.0, kz = 40000.0;
  const auto report = compensate_ankle_deflection(model, humanoid, centre, k, kz, ref);
  double mass = 0;
  for (const auto& [name, link] : urdf->links_)
    if (link->inertial)
      mass += link->inertial->mass;
  const double f = mass * 9.81 / 2;
  const Eigen::Vector3d right_arm = Eigen::Vector3d(0.0153, -0.0100, -0.105) - centre;
  const Eigen::Vector3d left_arm = Eigen::Vector3d(0.0153, 0.0100, -0.105) - centre;
  const double u = f / kz, theta_p = -right_arm.x() * f / k;
  const double theta_r_right = right_arm.y() * f / k, theta_r_left = left_arm.y() * f / k;
  std::printf("standing, c = (%g, %g, %g) m, k = %g N m/rad, k_z = %g N/m: u %.6f m (closed form "
              "%.6f), theta_p %.6f rad (%.6f), theta_r right %.6f (%.6f) left %.6f (%.6f); force "
              "mismatch %.2e N\n",
              centre.x(), centre.y(), centre.z(), k, kz, report.deflection(0, 0), u,
              report.deflection(0, 1), theta_p, report.deflection(0, 2), theta_r_right,
              report.deflection(0, 5), theta_r_left, report.max_force_mismatch);
  double distance = 0.0, angle = 0.0;
  for (int s = 0; s < ref.n_samples(); s += 50) {
    for (int foot = 0; foot < 2; ++foot) {
      EXPECT_NEAR(report.deflection(s, 3 * foot), u, 1e-9);
      EXPECT_NEAR(report.deflection(s, 3 * foot + 1), theta_p, 1e-6);
    }
    EXPECT_NEAR(report.deflection(s, 2), theta_r_right, 1e-6);
    EXPECT_NEAR(report.deflection(s, 5), theta_r_left, 1e-6);
    const auto [d, a] = foot_pose_error(*urdf, planned, ref, report.deflection, centre, s);
    distance = std::max(distance, d);
    angle = std::max(angle, a);
  }
  std::printf("  deflected foot vs plan %.2e m, %.2e rad (tol 1e-9)\n", distance, angle);
  EXPECT_LT(distance, 1e-9);
  EXPECT_LT(angle, 1e-9);
  // The loaded spring lifts the foot by u relative to the ankle: the leg stretches (less knee).
  for (int foot = 0; foot < 2; ++foot) {
    const int knee = humanoid.leg_columns[foot][3];
    EXPECT_LT(ref.q(0, knee), planned.q(0, knee));
  }
  // Only the leg columns change.
  std::vector<bool> is_leg(ref.q.cols(), false);
  for (const auto& columns : humanoid.leg_columns)
    for (int j : columns)
      is_leg[j] = true;
  for (int j = 0; j < ref.q.cols(); ++j)
    if (!is_leg[j]) {
      EXPECT_EQ((ref.q.col(j) - planned.q.col(j)).cwiseAbs().maxCoeff(), 0.0) << ref.joint_names[j];
    }
  EXPECT_EQ((ref.base_position - planned.base_position).cwiseAbs().maxCoeff(), 0.0);
  EXPECT_LT(report.max_force_mismatch, 1e-6);
}

TEST(AnkleCompensation, StandingClosedForm) {
  check_standing(Eigen::Vector3d::Zero()); // compliance centre at the ankle joint point
}

TEST(AnkleCompensation, StandingClosedFormOffsetComplianceCentre) {
  // Centre between the ankle and the sole, off to the side and forward: pitch vanishes (no
  // x arm), the roll arms are no longer symmetric.
  check_standing(Eigen::Vector3d(0.0153, 0.004, -0.05));
}

TEST(AnkleCompensation, SixStepWalk) {
  const plantar::multibody::Model model = hrp2_model();
  const Humanoid humanoid(model, hrp2_description());
  const auto urdf = parse_hrp2();
  const WalkingPattern walk = make_walking_pattern(model, humanoid, WalkingParameters{});
  JointReference ref = walk.reference;
  const Eigen::Vector3d centre = Eigen::Vector3d::Zero();
  const auto report = compensate_ankle_deflection(model, humanoid, centre, 600.0, 40000.0, ref);
  double distance = 0.0, angle = 0.0;
  for (int s = 0; s < ref.n_samples(); ++s) {
    const auto [d, a] = foot_pose_error(*urdf, walk.reference, ref, report.deflection, centre, s);
    distance = std::max(distance, d);
    angle = std::max(angle, a);
  }
  std::printf("six-step walk, k = 600 N m/rad, k_z = 40000 N/m: max u %.4f m, max |theta_p| "
              "%.4f rad, max |theta_r| %.4f rad, max ankle moment %.2f N m, ground force vs "
              "M (c'' - g) %.2e N, deflected foot vs plan %.2e m, %.2e rad\n",
              report.max_sag, report.max_pitch, report.max_roll, report.max_moment,
              report.max_force_mismatch, distance, angle);
  // The CoM column is the whole-body CoM of q_ref to 1e-10 m: second differences / T^2.
  EXPECT_LT(report.max_force_mismatch, 1e-2);
  EXPECT_LT(distance, 1e-9);
  EXPECT_LT(angle, 1e-9);
  // Single support: the whole weight on one spring, u = M g / k_z = 14 mm, plus dynamics.
  EXPECT_GT(report.max_sag, 0.013);
  EXPECT_LT(report.max_sag, 0.02);
  EXPECT_GT(report.max_roll, 0.0);
  EXPECT_LT(report.max_moment, 100.0);
  EXPECT_THROW(compensate_ankle_deflection(model, humanoid, centre, 0.0, 40000.0, ref),
               std::invalid_argument);
  JointReference short_ref = walk.reference;
  short_ref.resize(2, short_ref.period, short_ref.joint_names);
  EXPECT_THROW(compensate_ankle_deflection(model, humanoid, centre, 600.0, 40000.0, short_ref),
               std::invalid_argument);
}

} // namespace
