// The DCM stabilizer (multibody/walking/dcm_stabilizer.h) on the linear inverted pendulum
// (the cart-table model) whose ZMP is the desired one: the DCM error against the linear
// closed-loop model (e' = -k_p e - omega k_i E, E' = e - E / T_i; k_i = 0: e0 exp(-k_p t)),
// and one update's ZMP distribution, foot damping and force difference against hand values.
#include "multibody/walking/dcm_stabilizer.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

namespace plantar::walking {
namespace {

std::array<StabilizerFoot, 2> standing_feet(double right_fz, double left_fz) {
  std::array<StabilizerFoot, 2> feet;
  feet[0].position << 0, -0.1, 0;
  feet[1].position << 0, 0.1, 0;
  feet[0].force << 0, 0, right_fz;
  feet[1].force << 0, 0, left_fz;
  feet[0].contact = feet[1].contact = true;
  return feet;
}

/// The LIPM x'' = omega^2 (x - p), p = the stabilizer's desired ZMP, from a DCM error; returns
/// the worst |e_sim - e_linear| / |e0| over 1 s, e_linear from RK4 on the linear model.
double worst_deviation(double k_p, double k_i, double dt) {
  DcmStabilizerParameters parameters;
  const double g = 9.81, height = 0.8;
  parameters.omega = std::sqrt(g / height);
  parameters.dcm_gain = k_p;
  parameters.dcm_integral_gain = k_i;
  parameters.integral_time_constant = 2.0;
  DcmStabilizer stabilizer(parameters);
  const double w = parameters.omega;
  Eigen::Vector2d c(0.02, -0.01), cd(0.05, 0.03); // reference: c = 0 at rest
  const auto feet = standing_feet(300, 300);
  const Eigen::Vector2d zero = Eigen::Vector2d::Zero();
  const Eigen::Vector2d e0 = c + cd / w;
  // Linear model state (e, E) per axis.
  Eigen::Vector2d e_lin = e0, E_lin = zero;
  auto f = [&](const Eigen::Vector2d& e, const Eigen::Vector2d& E, Eigen::Vector2d& de,
               Eigen::Vector2d& dE) {
    de = -k_p * e - w * k_i * E;
    dE = e - E / parameters.integral_time_constant;
  };
  double worst = 0;
  const int n = static_cast<int>(std::lround(1.0 / dt));
  for (int step = 0; step < n; ++step) {
    const Eigen::Vector2d dcm = c + cd / w;
    worst = std::max(worst, (dcm - e_lin).norm() / e0.norm());
    stabilizer.update(dcm, zero, zero, feet, dt);
    const Eigen::Vector2d p = stabilizer.desired_zmp();
    // Exact LIPM step at constant p (cosh/sinh).
    const double ch = std::cosh(w * dt), sh = std::sinh(w * dt);
    const Eigen::Vector2d x = c - p;
    c = p + x * ch + cd * sh / w;
    cd = x * w * sh + cd * ch;
    // RK4 on the linear model.
    Eigen::Vector2d k1e, k1E, k2e, k2E, k3e, k3E, k4e, k4E;
    f(e_lin, E_lin, k1e, k1E);
    f(e_lin + 0.5 * dt * k1e, E_lin + 0.5 * dt * k1E, k2e, k2E);
    f(e_lin + 0.5 * dt * k2e, E_lin + 0.5 * dt * k2E, k3e, k3E);
    f(e_lin + dt * k3e, E_lin + dt * k3E, k4e, k4E);
    e_lin += dt / 6 * (k1e + 2 * k2e + 2 * k3e + k4e);
    E_lin += dt / 6 * (k1E + 2 * k2E + 2 * k3E + k4E);
  }
  if (k_i == 0) {
    const Eigen::Vector2d dcm = c + cd / w;
    std::printf("k_p = %g /s: DCM error after 1 s %.4e m, e0 exp(-k_p) = %.4e m\n", k_p, dcm.norm(),
                e0.norm() * std::exp(-k_p));
  }
  return worst;
}

TEST(DcmStabilizer, ClosedLoopDcmErrorFollowsTheLinearModel) {
  for (const double k_p : {2.0, 10.0}) {
    for (const double k_i : {0.0, 5.0}) {
      const double coarse = worst_deviation(k_p, k_i, 1e-3);
      const double fine = worst_deviation(k_p, k_i, 1e-4);
      std::printf("k_p = %g /s, k_i = %g /s: worst |e - e_linear| / |e0| = %.2e (dt = 1 ms), "
                  "%.2e (dt = 0.1 ms)\n",
                  k_p, k_i, coarse, fine);
      // Sample-and-hold of p over one period: first order in dt.
      EXPECT_LT(coarse, 0.02 * k_p / 10 + 0.01);
      EXPECT_LT(fine, 0.1 * coarse + 1e-6);
    }
  }
}

TEST(DcmStabilizer, DistributionFootDampingAndForceDifferenceAgainstHandValues) {
  DcmStabilizerParameters parameters;
  parameters.omega = 3.5;
  parameters.foot_damping = 2000;
  parameters.force_damping = 1e5;
  DcmStabilizer stabilizer(parameters);
  const double dt = 1e-3;
  // No DCM error: p_d = p_ref = (0.02, 0.05), between feet at y = -0.1 and 0.1: s = 0.75,
  // force targets (150, 450) N of the measured 600; CoP targets x = 0.02 at the sole centres.
  const auto feet = standing_feet(300, 300);
  stabilizer.update(Eigen::Vector2d::Zero(), Eigen::Vector2d::Zero(), Eigen::Vector2d(0.02, 0.05),
                    feet, dt);
  const auto& o = stabilizer.offsets();
  // pitch' = (0.02 - 0) 300 / 2000 = 3e-3 rad/s (toe down moves the CoP forward).
  EXPECT_NEAR(o[0].pitch, dt * 0.02 * 300 / 2000, 1e-15);
  EXPECT_NEAR(o[1].pitch, dt * 0.02 * 300 / 2000, 1e-15);
  EXPECT_NEAR(o[0].roll, 0, 1e-15);
  // z' = ((450 - 150) - 0) / 1e5: left lowered by z/2, right raised by z/2.
  const double z = dt * 300 / 1e5;
  EXPECT_NEAR(o[1].height, -z / 2, 1e-15);
  EXPECT_NEAR(o[0].height, z / 2, 1e-15);
  // A CoP target outside the sole is clamped to it (half size 0.1 m in x).
  DcmStabilizer far(parameters);
  far.update(Eigen::Vector2d::Zero(), Eigen::Vector2d::Zero(), Eigen::Vector2d(0.5, 0), feet, dt);
  EXPECT_NEAR(far.offsets()[0].pitch, dt * 0.1 * 300 / 2000, 1e-15);
  // Single support on the right: no force difference, the CoP target is p_d itself.
  auto single = standing_feet(600, 0);
  single[1].contact = false;
  DcmStabilizer one(parameters);
  one.update(Eigen::Vector2d::Zero(), Eigen::Vector2d::Zero(), Eigen::Vector2d(0, -0.08), single,
             dt);
  // roll' = (cop_y - target_y) f_z / D = (0 - 0.02) 600 / 2000 (target 0.02 left of centre).
  EXPECT_NEAR(one.offsets()[0].roll, dt * (-0.02) * 600 / 2000, 1e-15);
  EXPECT_EQ(one.offsets()[0].height, 0.0);
}

TEST(DcmStabilizer, CopTargetsStayInsideThePlannedSupport) {
  // The right sole rests on the triangle (0.1, -0.06), (0.1, 0.06), (-0.1, 0.06) of its outline
  // (a rectangle on three corners): the centre is on its hypotenuse. A CoP target at the
  // centre moves 1 cm inside it, along the hypotenuse's inward normal n = (0.06, 0.1) / |.|.
  DcmStabilizerParameters parameters;
  parameters.omega = 3.5;
  parameters.support_margin = 0.01;
  Eigen::Matrix2Xd triangle(2, 3);
  triangle << 0.1, 0.1, -0.1, -0.06, 0.06, 0.06;
  auto single = standing_feet(600, 0);
  single[1].contact = false;
  single[0].support = &triangle;
  DcmStabilizer one(parameters);
  const double dt = 1e-3;
  one.update(Eigen::Vector2d::Zero(), Eigen::Vector2d::Zero(), Eigen::Vector2d(0, -0.1), single,
             dt);
  const Eigen::Vector2d target = 0.01 * Eigen::Vector2d(0.06, 0.1).normalized();
  // roll' = (cop_y - target_y) f_z / D, pitch' = (target_x - cop_x) f_z / D (measured CoP 0).
  EXPECT_NEAR(one.offsets()[0].roll, dt * (0 - target.y()) * 600 / 2000, 1e-15);
  EXPECT_NEAR(one.offsets()[0].pitch, dt * target.x() * 600 / 2000, 1e-15);
  // Far outside, beyond the vertex (0.1, 0.06): the target is the shrunk triangle's vertex,
  // where the offset legs x = 0.09 and y = 0.05 meet.
  DcmStabilizer far(parameters);
  far.update(Eigen::Vector2d::Zero(), Eigen::Vector2d::Zero(), Eigen::Vector2d(0.5, 0.5), single,
             dt);
  EXPECT_NEAR(far.offsets()[0].roll, dt * (0 - 0.05) * 600 / 2000, 1e-15);
  EXPECT_NEAR(far.offsets()[0].pitch, dt * 0.09 * 600 / 2000, 1e-15);
}

} // namespace
} // namespace plantar::walking
