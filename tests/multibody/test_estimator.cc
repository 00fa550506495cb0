// The kinematic CoM/DCM estimator (multibody/walking/com_estimator.h) against the model's own
// CoM: HRP-2 at random poses (random base placement and joints) whose soles are where the
// reference says, read by exact sensors, gives the true CoM; a known CoM velocity (a base
// translation at constant speed) gives the true DCM once the filter has settled; the anchor
// follows the loaded foot; a support switch onto a foot off its reference moves the CoM
// estimate, not its velocity; compliant ankles' springs from the F/T wrenches match their static
// equilibrium.
#include "multibody/center_of_mass.h"
#include "multibody/kinematics.h"
#include "multibody/urdf_loader.h"
#include "multibody/walking/com_estimator.h"
#include "multibody/walking/humanoid.h"
#include "tests/multibody/test_helpers.h"

#include <Eigen/Geometry>
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

/// Wrenches carrying only the feet's normal forces (N).
std::array<multibody::Vector6d, 2> normal_wrenches(double right, double left) {
  std::array<multibody::Vector6d, 2> w;
  w[0] << 0, 0, right, 0, 0, 0;
  w[1] << 0, 0, left, 0, 0, 0;
  return w;
}

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
      estimator.update(r.encoders, r.orientation, r.soles,
                       normal_wrenches(300.0, n < 100 ? 0.0 : 250.0));
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
    estimator.update(r.encoders, r.orientation, r.soles,
                     normal_wrenches(n < 105 ? 300.0 : 0.0, n < 100 ? 0.0 : 300.0));
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

/// The ground's wrench [f; n] (world axes, n about the sole origin) on a frame as generalized
/// forces, by the principle of virtual work on central differences of the frame's placement:
/// tau_k = f . dp/dq_k + n . dtheta/dq_k (one-dof joints only; independent of the Jacobians).
double virtual_work(const multibody::Model& model, multibody::Data& data, Eigen::VectorXd q,
                    int frame, int k, const multibody::Vector6d& wrench) {
  const double h = 1e-6;
  q[k] += h;
  multibody::forward_kinematics(model, data, q);
  const multibody::SE3 plus = multibody::frame_placement(model, data, frame);
  q[k] -= 2 * h;
  multibody::forward_kinematics(model, data, q);
  const multibody::SE3 minus = multibody::frame_placement(model, data, frame);
  const Eigen::AngleAxisd turn(plus.rotation * minus.rotation.transpose());
  const Eigen::Vector3d dp = (plus.translation - minus.translation) / (2 * h);
  const Eigen::Vector3d dtheta = turn.angle() * turn.axis() / (2 * h);
  return wrench.head<3>().dot(dp) + wrench.tail<3>().dot(dtheta);
}

// Compliant ankles (three springs per foot, no encoder): with PassiveJointEstimate::wrench the
// estimate puts each spring where the sensed foot wrenches hold it in static equilibrium,
// k (q - rest) = tau, tau the wrenches' generalized forces. The truth here is that equilibrium
// found independently (a fixed point on the virtual work of central differences of the soles'
// placements), at random poses with random wrenches; with the springs at rest (the plan's
// default) the CoM estimate is off by the deflection's lever.
TEST(ComEstimator, CompliantAnkleSpringsFromTheForceSensors) {
  multibody::ModelOptions options;
  options.compliant_ankle.foot_links = {"RLEG_LINK5", "LLEG_LINK5"};
  options.compliant_ankle.center_in_foot = Eigen::Vector3d(0.01, 0.0, -0.05);
  const multibody::Model model =
      multibody::build_model_from_urdf(multibody::test::model_path("hrp2/hrp2.urdf"), options);
  const Humanoid humanoid(model, hrp2_description());
  multibody::Data data(model);
  const int imu = model.frame_id("CHEST_LINK1");
  std::vector<int> springs; // joint indices
  for (int joint = 1; joint < model.n_bodies; ++joint)
    if (model.nv_joint[joint] == 1 && model.passive_stiffness[model.idx_v[joint]] > 0)
      springs.push_back(joint);
  ASSERT_EQ(springs.size(), 6u);
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> uniform(-1.0, 1.0);
  double worst_spring = 0, worst_com = 0, worst_com_at_rest = 0, largest_deflection = 0;
  for (int trial = 0; trial < 5; ++trial) {
    Eigen::VectorXd q = multibody::test::random_configuration(model, rng);
    std::array<multibody::Vector6d, 2> world, sole;
    for (int foot = 0; foot < 2; ++foot)
      world[foot] << 60 * uniform(rng), 60 * uniform(rng), 300 + 100 * uniform(rng),
          20 * uniform(rng), 20 * uniform(rng), 5 * uniform(rng);
    // The springs' equilibrium: q_j = rest_j + sum_i tau_ij(q) / k_j, iterated to a fixed point.
    for (int j : springs)
      q[model.idx_q[j]] = model.passive_rest[model.idx_v[j]];
    for (int iteration = 0; iteration < 50; ++iteration) {
      Eigen::VectorXd next = q;
      for (int j : springs) {
        double tau = 0;
        for (int foot = 0; foot < 2; ++foot)
          tau +=
              virtual_work(model, data, q, humanoid.sole_frames[foot], model.idx_q[j], world[foot]);
        next[model.idx_q[j]] =
            model.passive_rest[model.idx_v[j]] + tau / model.passive_stiffness[model.idx_v[j]];
      }
      const double change = (next - q).lpNorm<Eigen::Infinity>();
      q = next;
      if (change < 1e-13)
        break;
    }
    const ExactReadings r = exact_readings(model, humanoid, imu, q, data);
    const Eigen::Vector3d com = multibody::center_of_mass(model, data);
    for (int foot = 0; foot < 2; ++foot) { // the F/T reading at the sole, sole axes
      const Eigen::Matrix3d rotation =
          multibody::frame_placement(model, data, humanoid.sole_frames[foot]).rotation;
      sole[foot] << rotation.transpose() * world[foot].head<3>(),
          rotation.transpose() * world[foot].tail<3>();
    }
    for (int j : springs)
      largest_deflection = std::max(largest_deflection, std::abs(q[model.idx_q[j]]));
    for (const PassiveJointEstimate passive :
         {PassiveJointEstimate::wrench, PassiveJointEstimate::plan}) {
      ComEstimatorParameters parameters;
      parameters.passive = passive;
      ComEstimator estimator(model, humanoid, imu, parameters, 1e-3);
      estimator.update(r.encoders, r.orientation, r.soles, sole);
      const double com_error = (estimator.com() - com).norm();
      if (passive == PassiveJointEstimate::plan) {
        worst_com_at_rest = std::max(worst_com_at_rest, com_error);
        continue;
      }
      worst_com = std::max(worst_com, com_error);
      for (int j : springs)
        worst_spring = std::max(
            worst_spring, std::abs(estimator.configuration()[model.idx_q[j]] - q[model.idx_q[j]]));
    }
  }
  std::printf("compliant ankles, 5 random poses and wrenches: deflections up to %.4f (m, rad); "
              "springs from the wrenches within %.2e, CoM within %.2e m (springs at rest: CoM "
              "off by up to %.4f m)\n",
              largest_deflection, worst_spring, worst_com, worst_com_at_rest);
  EXPECT_GT(largest_deflection, 0.02); // the springs do deflect
  EXPECT_LT(worst_spring, 1e-8);       // central differences: O(h^2) and round-off / h
  EXPECT_LT(worst_com, 1e-8);
  EXPECT_GT(worst_com_at_rest, 1e-3);
}

} // namespace
} // namespace plantar::walking
