// Step timing (multibody/walking/step_timing.h): its rate against hand values, and the closed
// loop on the linear inverted pendulum x'' = omega^2 (x - p): the walk of point feet with
// rectangular soles of step_adjustment_test.cc, its reference played at the time t_ref the
// timing runs (as played: the DCM at the rate r), the DCM stabilizer's desired ZMP clamped to
// the stance sole (the ankle strategy), pushed forward in single support. Without timing the DCM
// error diverges; with it the feet land earlier, where the plan put them, and the walk recovers.
#include "multibody/walking/dcm_stabilizer.h"
#include "multibody/walking/step_timing.h"
#include "tests/multibody/walking/lipm_walk_plan.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

namespace plantar::walking {
namespace {

const double omega = std::sqrt(9.81 / 0.8);

TEST(StepTiming, RateAgainstHandValues) {
  StepTimingParameters p;
  p.enabled = true;
  p.time_constant = 0.08;
  p.max_rate = 1.8;
  p.freeze_time = 0.1;
  const double dt = 1e-3;
  StepTiming timing(p);
  std::array<PlannedSwing, 2> swings;
  swings[1] = {0.3, 1.0};            // the left sole swings, its planned touchdown at t_ref = 1
  const Eigen::Vector2d v(0.3, 0.4); // |v| = 0.5 m/s
  const Eigen::Vector2d ahead(0.002, 0.001); // a deficit along v: d . v > 0
  // e . v = 0.01 * 0.3 + 0.005 * 0.4 = 0.005 m^2/s: lambda = 0.005 / 0.25 = 0.02 s.
  timing.update(0.5, swings, {false, false}, Eigen::Vector2d(0.01, 0.005), ahead, v, dt);
  EXPECT_NEAR(timing.lead(), 0.02, 1e-15);
  EXPECT_NEAR(timing.rate(), 1 + 0.02 / 0.08, 1e-15);
  EXPECT_NEAR(timing.advance(), 0.25 * dt, 1e-15);
  EXPECT_EQ(timing.shortened_swings(), 1);
  // A larger error: the rate is clamped; the same swing is counted once.
  timing.update(0.501, swings, {false, false}, Eigen::Vector2d(0.1, 0), ahead, v, dt);
  EXPECT_NEAR(timing.lead(), 0.12, 1e-15);
  EXPECT_EQ(timing.rate(), 1.8);
  EXPECT_NEAR(timing.advance(), 0.25 * dt + 0.8 * dt, 1e-15);
  EXPECT_EQ(timing.shortened_swings(), 1);
  EXPECT_EQ(timing.max_rate(), 1.8);
  // No deficit (the ankle takes the error), or one against the reference's motion: the plan's
  // rate, whatever the error.
  for (const Eigen::Vector2d& d : {Eigen::Vector2d(0, 0), Eigen::Vector2d(-0.01, 0.001)}) {
    timing.update(0.502, swings, {false, false}, Eigen::Vector2d(0.1, 0), d, v, dt);
    EXPECT_EQ(timing.lead(), 0.0);
    EXPECT_EQ(timing.rate(), 1.0);
  }
  // An error behind the reference with a deficit along it: lambda = 0.
  timing.update(0.503, swings, {false, false}, Eigen::Vector2d(-0.1, 0), ahead, v, dt);
  EXPECT_EQ(timing.rate(), 1.0);
  // The last freeze_time of the swing, and a touchdown read by the sensor: the plan's rate.
  timing.update(0.905, swings, {false, false}, Eigen::Vector2d(0.1, 0), ahead, v, dt);
  EXPECT_EQ(timing.rate(), 1.0);
  timing.update(0.6, swings, {false, true}, Eigen::Vector2d(0.1, 0), ahead, v, dt);
  EXPECT_EQ(timing.rate(), 1.0);
  // Double support (no swing, or both soles' plans swinging): the plan's rate.
  for (const PlannedSwing& s : {PlannedSwing{}, PlannedSwing{0.5, 1.0}}) {
    timing.update(0.6, {s, s}, {false, false}, Eigen::Vector2d(0.1, 0), ahead, v, dt);
    EXPECT_EQ(timing.rate(), 1.0);
  }
  // The next swing is counted again.
  swings = {PlannedSwing{0.1, 2.0}, PlannedSwing{}};
  timing.update(1.5, swings, {false, false}, Eigen::Vector2d(0.01, 0.005), ahead, v, dt);
  EXPECT_EQ(timing.shortened_swings(), 2);
  EXPECT_NEAR(timing.advance(), (0.25 + 0.8 + 0.25) * dt, 1e-15);
  // Off: the plan's rate.
  p.enabled = false;
  StepTiming off(p);
  off.update(0.5, swings, {false, false}, Eigen::Vector2d(0.1, 0), ahead, v, dt);
  EXPECT_EQ(off.rate(), 1.0);
  EXPECT_EQ(off.advance(), 0.0);
  // Bad parameters are named.
  for (int which = 0; which < 3; ++which) {
    StepTimingParameters bad;
    const char* expected = which == 0   ? "time constant = 0"
                           : which == 1 ? "max rate = 0.5"
                                        : "freeze time = -1";
    if (which == 0)
      bad.time_constant = 0;
    else if (which == 1)
      bad.max_rate = 0.5;
    else
      bad.freeze_time = -1;
    try {
      StepTiming t(bad);
      ADD_FAILURE() << expected;
    } catch (const std::invalid_argument& e) {
      EXPECT_NE(std::string(e.what()).find(expected), std::string::npos) << e.what();
    }
  }
}

/// The LIPM walk of step_adjustment_test.cc (stances of T = 0.8 s on (0.2 k, -+0.1), k even:
/// right; the last held 3 s; soles +-0.1 x +-0.06 m), its reference played at t_ref as the
/// balance loop takes it (its DCM c + r dc/dt_ref / omega; the ZMP reference the stance foot,
/// which the feet reach when the reference says). A push dv
/// (m/s) at t_push. The largest DCM error |xi - xi_ref(t_ref)| (m, capped at 1 m: a fall), the
/// last, the swings shortened and the advance t_ref - t at the end (s).
struct LipmWalk {
  double max_error = 0, final_error = 0, advance = 0, max_rate = 1;
  int shortened = 0;
};
LipmWalk lipm_walk(bool timed, const Eigen::Vector2d& push, double t_push) {
  const testing::LipmWalkPlan plan(omega);
  const double dt = 1e-3;
  DcmStabilizerParameters sp;
  sp.omega = omega;
  DcmStabilizer stabilizer(sp);
  StepTimingParameters tp;
  tp.enabled = timed;
  StepTiming timing(tp);
  Eigen::Vector2d c = plan.placement[0], cd = omega * (plan.dcm(0) - plan.placement[0]);
  // The plan's CoM at t_ref (c' = omega (xi - c) along the plan, stepped by dt r).
  Eigen::Vector2d c_plan = c;
  LipmWalk r;
  const int steps = static_cast<int>(std::lround(((plan.n - 1) * plan.T + 3) / dt));
  for (int i = 0; i < steps; ++i) {
    const double t = i * dt, t_ref = t + timing.advance();
    const int k = plan.stance_of(t_ref); // the feet land when the reference says
    const int stance = k % 2, swing = 1 - stance;
    std::array<StabilizerFoot, 2> feet;
    feet[stance].position.head<2>() = plan.placement[k];
    feet[stance].contact = true;
    feet[stance].force << 0, 0, 600;
    std::array<PlannedSwing, 2> swings;
    if (k < plan.n - 1)
      swings[swing] = {(t_ref - k * plan.T) / plan.T, (k + 1) * plan.T};
    // The reference as played at the rate r: its DCM c + r dc/dt_ref / omega.
    const Eigen::Vector2d xi_plan = plan.dcm(t_ref);
    const Eigen::Vector2d target = c_plan + timing.rate() * (xi_plan - c_plan);
    const Eigen::Vector2d xi = c + cd / omega;
    const double error = (xi - target).norm();
    r.max_error = std::max(r.max_error, std::min(error, 1.0));
    r.final_error = error;
    if (error > 1)
      break;
    stabilizer.update(xi, target, plan.placement[k], feet, dt);
    const Eigen::Vector2d p = stabilizer.desired_zmp() - stabilizer.zmp_deficit();
    const Eigen::Vector2d deficit =
        stabilizer.cop_excess(feet[stance], feet[stance].position.head<2>() + (xi - target));
    // The reference's DCM velocity, omega (xi_ref - p_ref) (p_ref: the stance foot).
    c_plan += omega * (xi_plan - c_plan) * (timing.rate() * dt);
    timing.update(t_ref, swings, {false, false}, xi - target, deficit,
                  omega * (target - plan.placement[k]), dt);
    plan.lipm_step(c, cd, p, dt);
    if (std::abs(t + dt - t_push) < 0.5 * dt)
      cd += push;
  }
  r.advance = timing.advance();
  r.max_rate = timing.max_rate();
  r.shortened = timing.shortened_swings();
  return r;
}

TEST(StepTiming, TheLipmWalkRecoversFromForwardPushesTheAnkleCannotTake) {
  // Unpushed: the stabilizer tracks the exact reference; the reference keeps the plan's time.
  for (bool timed : {false, true}) {
    const LipmWalk r = lipm_walk(timed, Eigen::Vector2d::Zero(), -1);
    EXPECT_LT(r.max_error, 1e-9);
    EXPECT_EQ(r.shortened, 0);
    EXPECT_EQ(r.advance, 0.0);
  }
  // Pushed forward in the third stance (right foot down, 1.6-2.4 s) at 1.9 s, 0.5 s before its
  // end: the DCM error jumps by dv / omega, past what the sole's toe can take (the ankle alone
  // recovers 0.35 m/s; with timing 0.44 m/s recovers, six swings shortened, 0.45 m/s falls).
  for (double dv : {0.38, 0.42}) {
    const LipmWalk ankle = lipm_walk(false, Eigen::Vector2d(dv, 0), 1.9);
    const LipmWalk timed = lipm_walk(true, Eigen::Vector2d(dv, 0), 1.9);
    std::printf("forward %.2f m/s: ankle only max error %.3f m; timed max %.3f m, final %.2e m, "
                "%d swings shortened, rate up to %.2f, %.0f ms ahead\n",
                dv, ankle.max_error, timed.max_error, timed.final_error, timed.shortened,
                timed.max_rate, timed.advance * 1e3);
    EXPECT_GE(ankle.max_error, 1.0) << dv;               // diverged: a fall
    EXPECT_LT(timed.max_error, 1.01 * dv / omega) << dv; // it stops growing
    EXPECT_LT(timed.final_error, 1e-4) << dv;
    EXPECT_GE(timed.shortened, 1) << dv;
    EXPECT_GT(timed.advance, 0.02) << dv;
  }
}

} // namespace
} // namespace plantar::walking
