// The swing-foot height with a touchdown velocity (issue 23): derivatives against finite
// differences, boundary values against the constraints, v = 0 against the paper's profile,
// the sampled plan, bad values.
#include "multibody/walking/footstep_plan.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <gtest/gtest.h>
#include <limits>
#include <stdexcept>
#include <string>

using namespace plantar::walking;

namespace {

WalkingParameters walk_with(double touchdown_velocity) {
  WalkingParameters walk;
  walk.touchdown_velocity = touchdown_velocity;
  return walk;
}

} // namespace

TEST(SwingHeight, DerivativesMatchFiniteDifferences) {
  // Central differences in tau (profiles) and in t (the height in m), step 1e-5: truncation
  // ~ h^2 |f'''| / 6 ~ 1e-8 and rounding ~ 1e-16 / h ~ 1e-11 relative.
  const double h = 1e-5;
  double max_profile = 0, max_height = 0;
  for (const double v : {0.0, 0.2, 0.5, 1.0}) {
    const WalkingParameters walk = walk_with(v);
    const double T = walk.single_support_time;
    for (double tau = 0.02; tau < 0.99; tau += 0.02) {
      const Eigen::Vector3d g = touchdown_profile(tau), gp = touchdown_profile(tau + h),
                            gm = touchdown_profile(tau - h);
      max_profile = std::max({max_profile, std::abs((gp(0) - gm(0)) / (2 * h) - g(1)),
                              std::abs((gp(1) - gm(1)) / (2 * h) - g(2))});
      const Eigen::Vector3d z = swing_foot_height(walk, tau), zp = swing_foot_height(walk, tau + h),
                            zm = swing_foot_height(walk, tau - h);
      // d/dt = (1 / T) d/dtau; scaled by the largest value of each derivative (~1, 1, 10).
      max_height = std::max({max_height, std::abs((zp(0) - zm(0)) / (2 * h * T) - z(1)),
                             std::abs((zp(1) - zm(1)) / (2 * h * T) - z(2)) / 10.0});
    }
  }
  std::printf("finite differences: touchdown profile %.2e, swing height %.2e (tol 1e-6)\n",
              max_profile, max_height);
  EXPECT_LT(max_profile, 1e-6);
  EXPECT_LT(max_height, 1e-6);
}

TEST(SwingHeight, BoundaryValuesMeetTheConstraints) {
  // The touchdown term: g = g' = g'' = 0 at 0, g = g' = 0 at 1/2, g(1) = 0, g'(1) = -1,
  // g''(1) = -14 (by hand: g = r (1 - tau), g'' = r'' (1 - tau) - 2 r', r'(1) = 7).
  const Eigen::Vector3d g0 = touchdown_profile(0.0), gh = touchdown_profile(0.5),
                        g1 = touchdown_profile(1.0);
  EXPECT_EQ(g0.cwiseAbs().maxCoeff(), 0.0);
  EXPECT_NEAR(gh(0), 0.0, 1e-16);
  EXPECT_NEAR(gh(1), 0.0, 1e-15);
  EXPECT_NEAR(g1(0), 0.0, 1e-15);
  EXPECT_NEAR(g1(1), -1.0, 1e-14);
  EXPECT_NEAR(g1(2), -14.0, 1e-13);
  for (const double v : {0.0, 0.1, 0.2, 0.7}) {
    const WalkingParameters walk = walk_with(v);
    const double H = walk.step_height;
    const Eigen::Vector3d z0 = swing_foot_height(walk, 0.0), zh = swing_foot_height(walk, 0.5),
                          z1 = swing_foot_height(walk, 1.0);
    // Apex: the largest height on a 1e-4 grid in tau.
    double apex = 0;
    for (int i = 0; i <= 10000; ++i)
      apex = std::max(apex, swing_foot_height(walk, i * 1e-4)(0));
    std::printf("v = %.1f m/s: z(0) = %.1e, z'(0) = %.1e, z''(0) = %.1e; z(1/2) = %.6f m, "
                "z'(1/2) = %.1e; z(1) = %.1e m, z'(1) = %.6f m/s; apex %.6f m (H = %.3f)\n",
                v, z0(0), z0(1), z0(2), zh(0), zh(1), z1(0), z1(1), apex, H);
    EXPECT_EQ(z0.cwiseAbs().maxCoeff(), 0.0);
    EXPECT_NEAR(zh(0), H, 1e-15);
    EXPECT_NEAR(zh(1), 0.0, 1e-14);
    EXPECT_NEAR(z1(0), 0.0, 1e-15);
    EXPECT_NEAR(z1(1), -v, 1e-14);
    EXPECT_NEAR(apex, H, 1e-15);
  }
  // At the bound v T = 19 H the apex is still H (the apex moves off tau = 1/2 past 19.2 H).
  WalkingParameters walk;
  walk.touchdown_velocity = 19.0 * walk.step_height / walk.single_support_time;
  double apex = 0;
  for (int i = 0; i <= 100000; ++i)
    apex = std::max(apex, swing_foot_height(walk, i * 1e-5)(0));
  std::printf("v = 19 H / T_ss = %.4f m/s: apex %.9f m (H = %.3f)\n", walk.touchdown_velocity, apex,
              walk.step_height);
  EXPECT_NEAR(apex, walk.step_height, 1e-15);
}

TEST(SwingHeight, ZeroTouchdownVelocityIsThePapersProfile) {
  // H * 64 tau^3 (1 - tau)^3 evaluated here, against the function and the sampled plan.
  const WalkingParameters walk;
  ASSERT_EQ(walk.touchdown_velocity, 0.0);
  const double H = walk.step_height;
  for (double tau = 0; tau <= 1.0; tau += 1.0 / 64) {
    const double expected = H * 64.0 * std::pow(tau * (1 - tau), 3);
    EXPECT_NEAR(swing_foot_height(walk, tau)(0), expected, 1e-16);
    EXPECT_EQ(swing_foot_height(walk, tau)(0), H * swing_height_profile(tau)(0));
  }
  const FootstepPlan plan = make_footstep_plan(walk);
  const double ss_start = walk.standing_before + walk.initial_double_support_time;
  double max_difference = 0;
  int n_swing = 0;
  for (int k = 0; k < plan.n_samples; ++k) {
    const double tau = (plan.time(k) - ss_start) / walk.single_support_time;
    if (plan.phase[k] == SupportPhase::left_support && tau < 1.0) { // the first step
      max_difference = std::max(max_difference, std::abs(plan.right_sole(k, 2) -
                                                         H * 64.0 * std::pow(tau * (1 - tau), 3)));
      ++n_swing;
    }
  }
  std::printf("first swing, %d samples: max |z - H 64 tau^3 (1 - tau)^3| = %.2e m\n", n_swing,
              max_difference);
  EXPECT_GT(n_swing, 100);
  EXPECT_LT(max_difference, 1e-15);
}

TEST(SwingHeight, PlanLandsWithTheTouchdownVelocity) {
  // The sampled plan: the swing sole's last samples against z(tau) and its backward
  // difference against -v (z'' = -14 v / T_ss at touchdown: the difference over one period T
  // differs from z'(1) = -v by about T / 2 |z''| = 7 v T / T_ss, 4.5 % at T = 5 ms; tolerance
  // 5 %); after touchdown z = 0.
  const WalkingParameters walk = walk_with(0.2);
  const FootstepPlan plan = make_footstep_plan(walk);
  const double T = walk.period, ss_start = walk.standing_before + walk.initial_double_support_time;
  int k_touchdown = 1;
  while (k_touchdown < plan.n_samples &&
         !(plan.phase[k_touchdown - 1] == SupportPhase::left_support &&
           plan.phase[k_touchdown] == SupportPhase::double_support))
    ++k_touchdown;
  ASSERT_LT(k_touchdown, plan.n_samples);
  EXPECT_NEAR(plan.time(k_touchdown), ss_start + walk.single_support_time, T + 1e-12);
  const double z_last = plan.right_sole(k_touchdown - 1, 2);
  const double tau_last = (plan.time(k_touchdown - 1) - ss_start) / walk.single_support_time;
  const double speed = (plan.right_sole(k_touchdown, 2) - z_last) / T;
  std::printf("touchdown sample %d: z before %.6e m (closed form %.6e), backward difference "
              "%.5f m/s (planned -0.2, tol 5 %%), z after %.1e m\n",
              k_touchdown, z_last, swing_foot_height(walk, tau_last)(0), speed,
              plan.right_sole(k_touchdown, 2));
  EXPECT_NEAR(z_last, swing_foot_height(walk, tau_last)(0), 1e-15);
  EXPECT_NEAR(speed, -0.2, 0.05 * 0.2);
  for (int k = k_touchdown; k < k_touchdown + 10; ++k)
    EXPECT_EQ(plan.right_sole(k, 2), 0.0);
}

TEST(SwingHeight, BadTouchdownVelocityIsRejected) {
  const double nan = std::numeric_limits<double>::quiet_NaN();
  for (const double v : {-0.01, 1.01, nan}) {
    try {
      check_walking_parameters(walk_with(v));
      ADD_FAILURE() << "touchdown_velocity = " << v << " accepted";
    } catch (const std::invalid_argument& e) {
      const std::string what = e.what();
      std::printf("v = %g: %s\n", v, e.what());
      EXPECT_NE(what.find("touchdown_velocity"), std::string::npos);
      EXPECT_NE(what.find("[0, 1] m/s"), std::string::npos);
    }
  }
  // Within [0, 1] m/s but past 19 H / T_ss: H = 0.01 m, T_ss = 0.78 s -> 0.2436 m/s.
  WalkingParameters walk = walk_with(0.3);
  walk.step_height = 0.01;
  try {
    check_walking_parameters(walk);
    ADD_FAILURE() << "touchdown_velocity = 0.3 with step_height = 0.01 accepted";
  } catch (const std::invalid_argument& e) {
    const std::string what = e.what();
    std::printf("%s\n", e.what());
    EXPECT_NE(what.find("touchdown_velocity = 0.3"), std::string::npos);
    EXPECT_NE(what.find("0.24359"), std::string::npos);
  }
  EXPECT_NO_THROW(check_walking_parameters(walk_with(1.0)));
}
