// Feed-forward compensation of the compliant-ankle deflection: the standing posture against
// the closed form (each foot carries M g / 2 at its sole centre), and the six-step walk: the
// ground force against M (c'' - g) of the reference's CoM column, and the deflected feet,
// recomposed by the test's own URDF chain, on their planned poses.
#include "multibody/walking/ankle_compensation.h"
#include "multibody/walking/walking_reference.h"
#include "tests/multibody/walking/urdf_fk.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <map>
#include <stdexcept>

namespace {

using namespace plantar::walking;
using plantar::walking::testing::link_pose;

const std::string kUrdf = std::string(PLANTAR_SOURCE_DIR) + "/models/hrp2/hrp2.urdf";

std::map<std::string, double> named_angles(const JointReference& ref, int k) {
  std::map<std::string, double> named;
  for (int i = 0; i < n_robot_joints; ++i)
    named[robot_joint_names()[i]] = ref.q(k, i);
  return named;
}

/// Largest distance (m) and rotation angle (rad), over both feet, between the planned foot
/// (LINK5 with the original q) and the compensated foot (LINK5 with the compensated q, then
/// the deflected spring Trans(0, 0, u) Ry(theta_p) Rx(theta_r)), by the test's own URDF chain.
std::pair<double, double> foot_pose_error(const urdf::ModelInterface& model,
                                          const JointReference& planned,
                                          const JointReference& compensated,
                                          const Eigen::Matrix<double, Eigen::Dynamic, 6>& theta,
                                          int k) {
  double distance = 0.0, angle = 0.0;
  const char* links[2] = {"RLEG_LINK5", "LLEG_LINK5"};
  for (int foot = 0; foot < 2; ++foot) {
    const Eigen::Isometry3d before = link_pose(model, links[foot], named_angles(planned, k));
    Eigen::Isometry3d spring = Eigen::Isometry3d::Identity();
    spring.translate(Eigen::Vector3d(0, 0, theta(k, 3 * foot)));
    spring.rotate(Eigen::AngleAxisd(theta(k, 3 * foot + 1), Eigen::Vector3d::UnitY()));
    spring.rotate(Eigen::AngleAxisd(theta(k, 3 * foot + 2), Eigen::Vector3d::UnitX()));
    const Eigen::Isometry3d after =
        link_pose(model, links[foot], named_angles(compensated, k)) * spring;
    distance = std::max(distance, (before.translation() - after.translation()).norm());
    angle =
        std::max(angle, Eigen::AngleAxisd(before.linear().transpose() * after.linear()).angle());
  }
  return {distance, angle};
}

TEST(AnkleCompensation, StandingClosedForm) {
  const auto model = load_urdf(kUrdf);
  const JointReference planned = make_standing_reference(*model, 1.0);
  JointReference ref = planned;
  const double k = 600.0, kz = 40000.0;
  const auto report = compensate_ankle_deflection(*model, k, kz, ref);
  // Static: each sole carries M g / 2 at its centre, (0.0153, -+0.0100, -0.105) m from the
  // ankle (docs/hrp2_model.md): u = M g / (2 k_z), theta_r = dy M g / (2 k),
  // theta_p = -dx M g / (2 k).
  double mass = 0;
  for (const auto& [name, link] : model->links_)
    if (link->inertial)
      mass += link->inertial->mass;
  const double f = mass * 9.81 / 2;
  const double u = f / kz, theta_p = -0.0153 * f / k, theta_r = 0.0100 * f / k;
  std::printf("standing, k = %g N m/rad, k_z = %g N/m: u %.6f m (closed form %.6f), theta_p "
              "%.6f rad (%.6f), theta_r right %.6f left %.6f (-+%.6f); force mismatch %.2e N\n",
              k, kz, report.deflection(0, 0), u, report.deflection(0, 1), theta_p,
              report.deflection(0, 2), report.deflection(0, 5), theta_r, report.max_force_mismatch);
  for (int s = 0; s < ref.n_samples(); s += 50) {
    for (int foot = 0; foot < 2; ++foot) {
      EXPECT_NEAR(report.deflection(s, 3 * foot), u, 1e-9);
      EXPECT_NEAR(report.deflection(s, 3 * foot + 1), theta_p, 1e-6);
    }
    EXPECT_NEAR(report.deflection(s, 2), -theta_r, 1e-6);
    EXPECT_NEAR(report.deflection(s, 5), theta_r, 1e-6);
    const auto [distance, angle] = foot_pose_error(*model, planned, ref, report.deflection, s);
    EXPECT_LT(distance, 1e-9);
    EXPECT_LT(angle, 1e-9);
  }
  // The loaded spring lifts the foot by u relative to the ankle: the leg stretches (less knee).
  EXPECT_LT(ref.q(0, 3), planned.q(0, 3));
  EXPECT_LT(report.max_force_mismatch, 1e-6);
}

TEST(AnkleCompensation, SixStepWalk) {
  const auto model = load_urdf(kUrdf);
  const WalkingPattern walk = make_walking_pattern(*model, WalkingParameters{});
  JointReference ref = walk.reference;
  const auto report = compensate_ankle_deflection(*model, 600.0, 40000.0, ref);
  double distance = 0.0, angle = 0.0;
  for (int s = 0; s < ref.n_samples(); ++s) {
    const auto [d, a] = foot_pose_error(*model, walk.reference, ref, report.deflection, s);
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
  EXPECT_THROW(compensate_ankle_deflection(*model, 0.0, 40000.0, ref), std::invalid_argument);
}

} // namespace
