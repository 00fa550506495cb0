// JointReference::sample: cubic Hermite interpolation of the sampled walking reference.
//  * exact (round-off) for quadratics in t, joints and base position, between interior samples;
//  * C1: the finite-difference velocity a PD playback uses, (q(t) - q(t - dt)) / dt, changes
//    between consecutive steps by O(dt max|q''|) also across the samples, where linear
//    interpolation jumps by O(period max|q''|) (the 1/dt acceleration spikes of the walk).
#include "multibody/walking/joint_reference.h"

#include <cmath>
#include <cstdio>
#include <fstream>
#include <gtest/gtest.h>
#include <sstream>
#include <string>
#include <vector>

using namespace plantar::walking;

namespace {

constexpr int kJoints = 30; // any number of columns; 30 as HRP-2

std::vector<std::string> joint_names(int n) {
  std::vector<std::string> names;
  for (int j = 0; j < n; ++j)
    names.push_back("joint_" + std::to_string(j));
  return names;
}

JointReference make_reference(double period, int n, double (*f)(int joint, double t),
                              int n_joints = kJoints) {
  JointReference ref;
  ref.resize(n, period, joint_names(n_joints));
  for (int k = 0; k < n; ++k) {
    const double t = k * period;
    Eigen::VectorXd angles(n_joints);
    for (int j = 0; j < n_joints; ++j)
      angles[j] = f(j, t);
    Eigen::Isometry3d base = Eigen::Isometry3d::Identity();
    base.translation() = Eigen::Vector3d(f(0, t), f(1, t), f(2, t));
    ref.set(k, base, angles, Eigen::Vector3d::Zero());
  }
  return ref;
}

double quadratic(int j, double t) {
  return 0.1 * j - (0.5 + 0.01 * j) * t + (2.0 - 0.1 * j) * t * t;
}
double wave(int j, double t) {
  return 0.3 * std::sin((2.0 + 0.1 * j) * t + j);
}

} // namespace

TEST(JointReference, CubicHermiteIsExactForQuadratics) {
  const double period = 0.005;
  const JointReference ref = make_reference(period, 60, quadratic);
  EXPECT_EQ(ref.q.rows(), 60);
  EXPECT_EQ(ref.q.cols(), kJoints);
  EXPECT_EQ(ref.joint_names, joint_names(kJoints));
  Eigen::VectorXd q(kJoints);
  Eigen::Isometry3d base;
  double worst = 0.0;
  for (int i = 0; i <= 1000; ++i) {
    const double t = period + (ref.duration() - 2 * period) * i / 1000.0; // interior tangents
    ref.sample(t, q, base);
    for (int j = 0; j < kJoints; ++j)
      worst = std::max(worst, std::abs(q[j] - quadratic(j, t)));
    for (int c = 0; c < 3; ++c)
      worst = std::max(worst, std::abs(base.translation()[c] - quadratic(c, t)));
  }
  std::printf("quadratic reference: max interpolation error %.2e rad (tol 1e-13)\n", worst);
  EXPECT_LE(worst, 1e-13);
  // Samples are reproduced exactly, the ends included.
  ref.sample(0.0, q, base);
  EXPECT_EQ(q[3], quadratic(3, 0.0));
  ref.sample(ref.duration(), q, base);
  EXPECT_NEAR(q[3], quadratic(3, ref.duration()), 1e-15);
}

TEST(JointReference, FiniteDifferenceVelocityHasNoJumpsAtSamples) {
  const double period = 0.005, dt = 1e-4;
  const JointReference ref = make_reference(period, 400, wave);
  Eigen::VectorXd q(kJoints), q_prev(kJoints), v(kJoints);
  Eigen::VectorXd v_prev = Eigen::VectorXd::Zero(kJoints);
  Eigen::Isometry3d base;
  double max_jump = 0.0, max_accel = 0.0;
  ref.sample(0.0, q_prev, base);
  for (int n = 1; n * dt <= ref.duration(); ++n) {
    ref.sample(n * dt, q, base);
    v = (q - q_prev) / dt;
    if (n >= 2 && n * dt > 2 * period && n * dt < ref.duration() - 2 * period)
      max_jump = std::max(max_jump, (v - v_prev).cwiseAbs().maxCoeff());
    v_prev = v;
    q_prev = q;
  }
  for (int j = 0; j < kJoints; ++j)
    max_accel = std::max(max_accel, 0.3 * std::pow(2.0 + 0.1 * j, 2));
  // Linear interpolation would jump by about period max|q''| = 50 dt max|q''| at each sample.
  std::printf("FD velocity of the reference at dt = %.0e s: max change per step %.3e rad/s, "
              "dt max|q''| = %.3e, linear interpolation ~ %.3e\n",
              dt, max_jump, dt * max_accel, period * max_accel);
  EXPECT_LE(max_jump, 2.0 * dt * max_accel);
}

TEST(JointReference, AnyNumberOfJointsAndCsvColumns) {
  // A 7-joint robot: the columns and the CSV header follow joint_names.
  const double period = 0.01;
  const JointReference ref = make_reference(period, 5, quadratic, 7);
  Eigen::VectorXd q(7);
  Eigen::Isometry3d base;
  ref.sample(2.5 * period, q, base);
  double worst = 0.0; // interior: exact for the quadratic
  for (int j = 0; j < 7; ++j)
    worst = std::max(worst, std::abs(q[j] - quadratic(j, 2.5 * period)));
  EXPECT_LE(worst, 1e-13);
  const std::string path = "joint_reference_test_7.csv";
  ref.write_csv(path);
  std::ifstream in(path);
  std::string header, line;
  ASSERT_TRUE(std::getline(in, header));
  std::string expected = "t,base_x,base_y,base_z,base_qw,base_qx,base_qy,base_qz,com_x,com_y,com_z";
  for (const std::string& name : joint_names(7))
    expected += "," + name;
  EXPECT_EQ(header, expected);
  int rows = 0;
  while (std::getline(in, line)) {
    ++rows;
    std::stringstream fields(line);
    std::string field;
    int n_fields = 0;
    while (std::getline(fields, field, ','))
      ++n_fields;
    EXPECT_EQ(n_fields, 11 + 7) << line;
  }
  EXPECT_EQ(rows, 5);
  std::remove(path.c_str());
}
