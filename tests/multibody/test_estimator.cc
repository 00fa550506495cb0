// The kinematic CoM/DCM estimator (multibody/walking/com_estimator.h) against the model's own
// CoM: HRP-2 at random poses (random base placement and joints) whose soles are where the
// reference says, read by exact sensors, gives the true CoM; a known CoM velocity (a base
// translation at constant speed) gives the true DCM once the filter has settled; the anchor
// follows the loaded foot; a support switch onto a foot off its reference moves the CoM
// estimate, not its velocity.
#include "multibody/center_of_mass.h"
#include "multibody/kinematics.h"
#include "multibody/urdf_loader.h"
#include "multibody/walking/com_estimator.h"
#include "multibody/walking/humanoid.h"
#include "tests/multibody/test_helpers.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

namespace plantar::walking {
namespace {

HumanoidDescription hrp2_description() {
  HumanoidDescription d;
  d.base_link = "BODY";
  d.foot_links = {"RLEG_LINK5", "LLEG_LINK5"};
  d.sole_frames = {"r_sole", "l_sole"};
  return d;
}

/// What exact sensors read at q: the joints, the IMU frame's orientation and the soles where
/// the kinematics put them (the reference's soles for a robot exactly on its plan).
struct ExactReadings {
  Eigen::VectorXd encoders;
  Eigen::Matrix3d orientation;
  std::array<Eigen::Vector3d, 2> soles;
};

/// @p data receives the kinematics at @p q.
ExactReadings exact_readings(const multibody::Model& model, const Humanoid& humanoid, int imu,
                             const Eigen::VectorXd& q, multibody::Data& data) {
  multibody::forward_kinematics(model, data, q);
  ExactReadings r;
  r.encoders.resize(humanoid.n_joints());
  for (int j = 0; j < humanoid.n_joints(); ++j)
    r.encoders[j] = q[model.idx_q[humanoid.joints[j]]];
  r.orientation = multibody::frame_placement(model, data, imu).rotation;
  for (int foot = 0; foot < 2; ++foot)
    r.soles[foot] = multibody::frame_placement(model, data, humanoid.sole_frames[foot]).translation;
  return r;
}

TEST(ComEstimator, ExactSensorsGiveTheTrueCentreOfMassAndDcm) {
  const multibody::Model model =
      multibody::build_model_from_urdf(multibody::test::model_path("hrp2/hrp2.urdf"));
  const Humanoid humanoid(model, hrp2_description());
  multibody::Data data(model);
  const int imu = model.frame_id("CHEST_LINK1"); // an IMU away from the base
  const double dt = 1e-3, omega = 3.5;
  std::mt19937 rng(5);
  double worst_com = 0, worst_dcm = 0;
  for (int trial = 0; trial < 5; ++trial) {
    const Eigen::VectorXd q0 = multibody::test::random_configuration(model, rng);
    ComEstimatorParameters parameters;
    parameters.velocity_time_constant = 0.005;
    ComEstimator estimator(model, humanoid, imu, parameters, dt);
    const Eigen::Vector3d velocity(0.1, -0.05, 0.02); // base translation, m/s
    for (int n = 0; n <= 200; ++n) {
      Eigen::VectorXd q = q0;
      q.head<3>() += n * dt * velocity;
      const ExactReadings r = exact_readings(model, humanoid, imu, q, data);
      // Only the right foot loaded during the first half, then both.
      const std::array<double, 2> forces{300.0, n < 100 ? 0.0 : 250.0};
      estimator.update(r.encoders, r.orientation, r.soles, forces);
      const Eigen::Vector3d com = multibody::center_of_mass(model, data);
      worst_com = std::max(worst_com, (estimator.com() - com).norm());
      if (n == 200) // the CoM moves with the base: c' = velocity
        worst_dcm = std::max(worst_dcm, (estimator.dcm(omega) - (com + velocity / omega)).norm());
    }
  }
  std::printf("exact sensors, 5 random poses: worst CoM error %.2e m, DCM error after 0.2 s "
              "(filter 5 ms) %.2e m\n",
              worst_com, worst_dcm);
  EXPECT_LT(worst_com, 1e-12);
  EXPECT_LT(worst_dcm, 1e-9);
}

// The robot moves at a known velocity while its support switches from the right foot to the left
// and the reference puts the left sole 1 cm off where the kinematics find it (a foot that
// landed off its plan): the CoM estimate jumps by that offset, the CoM velocity estimate must
// not (it is the change over each period with one anchor; before, each half-centimetre step of
// the anchor over a 1 ms period entered the velocity filter as 5 m/s).
TEST(ComEstimator, ASupportSwitchMovesTheAnchorNotTheVelocity) {
  const multibody::Model model =
      multibody::build_model_from_urdf(multibody::test::model_path("hrp2/hrp2.urdf"));
  const Humanoid humanoid(model, hrp2_description());
  multibody::Data data(model);
  const int imu = model.frame_id("CHEST_LINK1");
  const double dt = 1e-3;
  std::mt19937 rng(7);
  const Eigen::VectorXd q0 = multibody::test::random_configuration(model, rng);
  ComEstimatorParameters parameters;
  parameters.velocity_time_constant = 0.002; // settled to round-off from zero by n = 90
  ComEstimator estimator(model, humanoid, imu, parameters, dt);
  const Eigen::Vector3d velocity(0.1, -0.05, 0.0), offset(0.0, 0.01, 0.0);
  double worst_velocity = 0, jump = 0;
  Eigen::Vector3d previous_error = Eigen::Vector3d::Zero();
  for (int n = 0; n <= 200; ++n) {
    Eigen::VectorXd q = q0;
    q.head<3>() += n * dt * velocity;
    ExactReadings r = exact_readings(model, humanoid, imu, q, data);
    r.soles[1] += offset;
    // Right foot alone, 5 ms of both (weights 1/2), then the left alone.
    const std::array<double, 2> forces{n < 105 ? 300.0 : 0.0, n < 100 ? 0.0 : 300.0};
    estimator.update(r.encoders, r.orientation, r.soles, forces);
    const Eigen::Vector3d error = estimator.com() - multibody::center_of_mass(model, data);
    jump = std::max(jump, (error - previous_error).norm());
    previous_error = error;
    if (n >= 90) // the filter has settled on the true velocity
      worst_velocity = std::max(worst_velocity, (estimator.com_velocity() - velocity).norm());
  }
  std::printf("support switch onto a foot 1 cm off its reference: CoM estimate jumps by at most "
              "%.4f m per period, its velocity stays within %.2e m/s of the truth\n",
              jump, worst_velocity);
  EXPECT_NEAR(previous_error.norm(), 0.01, 1e-12); // anchored on the left foot: off by 1 cm
  EXPECT_NEAR(jump, 0.005, 1e-12);                 // two jumps of half the offset
  EXPECT_LT(worst_velocity, 1e-9);
}

} // namespace
} // namespace plantar::walking
