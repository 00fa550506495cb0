// Step adjustment (multibody/walking/step_adjustment.h): its update against hand values, its
// reference shifts against the LIPM they stand for (dxi' = omega (dxi - dp), dc' = omega (dxi -
// dc)), and the closed loop on the linear inverted pendulum x'' = omega^2 (x - p): a walk of
// point feet with rectangular soles, the DCM stabilizer's desired ZMP clamped to the stance sole
// (the ankle strategy), pushed in single support. Without step adjustment the DCM error diverges;
// with it the walk recovers.
#include "multibody/walking/dcm_stabilizer.h"
#include "multibody/walking/step_adjustment.h"
#include "tests/multibody/walking/lipm_walk_plan.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

namespace plantar::walking {
namespace {

const double omega = std::sqrt(9.81 / 0.8);
const std::array<Eigen::Matrix2d, 2> straight{Eigen::Matrix2d::Identity(),
                                              Eigen::Matrix2d::Identity()};

/// Feet that land exactly where they are commanded.
std::array<Eigen::Vector2d, 2> placed(const StepAdjustment& step) {
  return {step.foot_shift(0), step.foot_shift(1)};
}

TEST(StepAdjustment, OneUpdateAgainstHandValues) {
  StepAdjustmentParameters p;
  p.enabled = true;
  p.gain = 0.8;
  p.max_forward = 0.15;
  p.max_outward = 0.07;
  p.max_inward = 0.01;
  p.freeze_time = 0.1;
  p.max_target_speed = 1e9; // checked at the end
  const double gain = 1 + 10 / omega, dt = 1e-3;
  for (int foot = 0; foot < 2; ++foot) {
    StepAdjustment step(p);
    std::array<PlannedSwing, 2> swings;
    swings[foot] = {0.25, 1.0}; // lift-off, 0.6 s to the planned touchdown at t = 0.4
    const Eigen::Vector2d deficit(0.01, 0.01);
    step.update(0.4, swings, straight, {false, false}, placed(step), deficit, omega, gain, dt);
    // x: 0.8 * 0.01 / gain * exp(0.6 omega); y: outward is -y for the right foot.
    const double grow = p.gain / gain * std::exp(omega * 0.6);
    EXPECT_NEAR(step.landing_target().x(), 0.01 * grow, 1e-14);
    const double y = 0.01 * grow; // 0.0168: inside outward (left) and past inward (right)
    EXPECT_NEAR(step.landing_target().y(), foot == 0 ? p.max_inward : y, 1e-14);
    EXPECT_NEAR((step.foot_shift(foot) - 0.25 * step.landing_target()).norm(), 0, 1e-15);
    EXPECT_EQ(step.foot_shift(1 - foot).norm(), 0.0);
    EXPECT_NEAR((step.dcm_shift() - step.landing_target() * std::exp(-omega * 0.6)).norm(), 0,
                1e-15);
    EXPECT_EQ(step.zmp_shift().norm(), 0.0);
    EXPECT_NEAR((step.com_shift() - (1 - std::exp(-omega * dt)) * step.dcm_shift()).norm(), 0,
                1e-16);
    // A larger deficit: clamped forward and outward.
    step.update(0.401, swings, straight, {false, false}, placed(step),
                Eigen::Vector2d(1, foot == 0 ? -1 : 1), omega, gain, dt);
    EXPECT_NEAR(step.landing_target().x(), p.max_forward, 1e-15);
    EXPECT_NEAR(step.landing_target().y(), foot == 0 ? -p.max_outward : p.max_outward, 1e-15);
    const Eigen::Vector2d held = step.landing_target();
    // A touchdown read by the sensor, and the last freeze_time: held.
    std::array<bool, 2> touched{false, false};
    touched[foot] = true;
    step.update(0.402, swings, straight, touched, placed(step), Eigen::Vector2d(-1, 0), omega, gain,
                dt);
    EXPECT_EQ(step.landing_target(), held);
    // The sensor reads the sole 3 mm ahead and 2 mm left of its target (its last unloaded
    // reading is the landing).
    const Eigen::Vector2d landed = held + Eigen::Vector2d(0.003, 0.002);
    std::array<Eigen::Vector2d, 2> sensed{Eigen::Vector2d::Zero(), Eigen::Vector2d::Zero()};
    sensed[foot] = landed;
    step.update(0.905, swings, straight, {false, false}, sensed, Eigen::Vector2d(-1, 0), omega,
                gain, dt);
    EXPECT_EQ(step.landing_target(), held);
    // Landing, the foot down: the plan's shift and the sole's anchor are the sensed landing; the
    // leg's command leaves the target towards it.
    swings[foot] = {-1, -1};
    step.update(1.001, swings, straight, touched, placed(step), Eigen::Vector2d(-1, 0), omega, gain,
                dt);
    EXPECT_EQ(step.plan_shift(), landed);
    EXPECT_EQ(step.anchor_shift(foot), landed);
    EXPECT_EQ(step.dcm_shift(), landed);
    const double relax = 1 - std::exp(-dt / p.landing_time_constant);
    EXPECT_NEAR((step.foot_shift(foot) - (held + relax * (landed - held))).norm(), 0, 1e-15);
    EXPECT_EQ(step.adjusted_steps(), 1);
    EXPECT_NEAR(step.max_adjustment(), held.norm(), 1e-15);
    EXPECT_NEAR(step.max_landing_error(), std::hypot(0.003, 0.002), 1e-15);
  }
  // A late touchdown: at the planned touchdown the unloaded foot is taken at its target; its
  // sensed landing becomes the plan's shift when its sensor reads the touchdown.
  {
    StepAdjustment late(p);
    late.update(0.4, {PlannedSwing{0.5, 1.0}, PlannedSwing{}}, straight, {false, false},
                placed(late), Eigen::Vector2d(0.01, 0), omega, gain, dt);
    const Eigen::Vector2d target = late.landing_target();
    ASSERT_GT(target.norm(), 1e-3);
    late.update(1.001, {PlannedSwing{}, PlannedSwing{}}, straight, {false, false}, placed(late),
                Eigen::Vector2d::Zero(), omega, gain, dt);
    EXPECT_EQ(late.plan_shift(), target);
    EXPECT_EQ(late.anchor_shift(0), target);
    EXPECT_EQ(late.dcm_shift(), target);
    const Eigen::Vector2d down = target + Eigen::Vector2d(-0.004, 0.001);
    late.update(1.002, {PlannedSwing{}, PlannedSwing{}}, straight, {false, false},
                {down, Eigen::Vector2d::Zero()}, Eigen::Vector2d::Zero(), omega, gain, dt);
    EXPECT_EQ(late.plan_shift(), target);
    late.update(1.003, {PlannedSwing{}, PlannedSwing{}}, straight, {true, false},
                {down + Eigen::Vector2d(0.01, 0), Eigen::Vector2d::Zero()}, Eigen::Vector2d::Zero(),
                omega, gain, dt);
    EXPECT_EQ(late.plan_shift(), down);
    EXPECT_EQ(late.anchor_shift(0), down);
    EXPECT_NEAR(late.max_landing_error(), std::hypot(0.004, 0.001), 1e-15);
  }
  // A rotated landing sole: the clamp acts in its axes.
  StepAdjustment step(p);
  const double yaw = 0.5;
  std::array<Eigen::Matrix2d, 2> turned = straight;
  turned[1] << std::cos(yaw), -std::sin(yaw), std::sin(yaw), std::cos(yaw);
  step.update(0.4, {PlannedSwing{}, PlannedSwing{0.5, 1.0}}, turned, {false, false}, placed(step),
              Eigen::Vector2d(1, 0), omega, gain, dt);
  const Eigen::Vector2d local = turned[1].transpose() * step.landing_target();
  EXPECT_NEAR(local.x(), p.max_forward, 1e-15);
  EXPECT_NEAR(local.y(), -p.max_inward, 1e-15);
  // The target's speed limit: one period moves it by max_target_speed dt along the move.
  p.max_target_speed = 2;
  StepAdjustment slow(p);
  slow.update(0.4, {PlannedSwing{0.5, 1.0}, PlannedSwing{}}, straight, {false, false}, placed(slow),
              Eigen::Vector2d(0.03, -0.04), omega, gain, dt);
  EXPECT_NEAR((slow.landing_target() - 2 * dt * Eigen::Vector2d(0.6, -0.8)).norm(), 0, 1e-15);
  // Off: nothing moves.
  p.enabled = false;
  StepAdjustment off(p);
  off.update(0.4, {PlannedSwing{0.5, 1.0}, PlannedSwing{}}, straight, {false, false}, placed(off),
             Eigen::Vector2d(1, 1), omega, gain, dt);
  EXPECT_EQ(off.landing_target().norm() + off.dcm_shift().norm() + off.foot_shift(0).norm(), 0.0);
  // Bad parameters are named.
  p.gain = 3;
  try {
    StepAdjustment bad(p);
    FAIL();
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("gain = 3"), std::string::npos) << e.what();
  }
}

TEST(StepAdjustment, ShiftsSolveTheTranslatedPendulum) {
  // One deficit at t = 0.2 of a swing ending at t = 1, then none: between updates dxi must
  // follow dxi' = omega (dxi - dp) and dc' = omega (dxi - dc) (central differences against the
  // right-hand sides), and after the landing dc -> S as exp(-omega t).
  StepAdjustmentParameters p;
  p.enabled = true;
  p.max_target_speed = 1e9;
  StepAdjustment step(p);
  const double dt = 1e-4, gain = 1 + 10 / omega;
  std::vector<double> time, xi, c, dp;
  for (int k = 0; k <= 20000; ++k) {
    const double t = k * dt;
    const std::array<PlannedSwing, 2> swings{PlannedSwing{t < 1 ? t : -1.0, t < 1 ? 1.0 : -1.0},
                                             PlannedSwing{}};
    step.update(t, swings, straight, {false, false},
                {step.landing_target(), Eigen::Vector2d::Zero()},
                Eigen::Vector2d(k == 2000 ? 0.01 : 0.0, 0.0), omega, gain, dt);
    time.push_back(t);
    xi.push_back(step.dcm_shift().x());
    c.push_back(step.com_shift().x());
    dp.push_back(step.zmp_shift().x());
  }
  const double S = step.plan_shift().x();
  EXPECT_NEAR(S, 0.01 / gain * std::exp(omega * 0.8), 1e-12);
  double worst_xi = 0, worst_c = 0;
  for (std::size_t k = 2002; k + 1 < time.size(); ++k) {
    if (std::abs(time[k] - 1.0) < 3 * dt)
      continue; // the landing: dp steps
    worst_xi =
        std::max(worst_xi, std::abs((xi[k + 1] - xi[k - 1]) / (2 * dt) - omega * (xi[k] - dp[k])));
    worst_c = std::max(worst_c, std::abs((c[k + 1] - c[k - 1]) / (2 * dt) -
                                         omega * (0.5 * (xi[k] + xi[k + 1]) - c[k])));
  }
  std::printf("dxi residual %.3g m/s, dc residual %.3g m/s (S = %.4f m)\n", worst_xi, worst_c, S);
  EXPECT_LT(worst_xi, 1e-6 * S * omega * omega);
  EXPECT_LT(worst_c, 1e-3 * S * omega);
  EXPECT_NEAR(xi.back(), S, 1e-15);
  // dc at t = 2 from its value at t = 1.5: exponential approach.
  const double c15 = c[15000];
  EXPECT_NEAR(c.back(), S + (c15 - S) * std::exp(-omega * 0.5), 1e-9 * S);
}

/// The LIPM walk: stances of T = 0.8 s on placements (0.2 k, -+0.1) (k even: right), the last
/// one held 3 s; ZMP = the stabilizer's CoP target clamped to the stance sole (+-0.1, +-0.06);
/// a push dv (m/s) at t_push. Returns the largest DCM error |xi - xi_ref - dxi| (m), capped at
/// 1 m (a fall), and the step adjustment's landings moved and largest move.
struct LipmWalk {
  double max_error = 0, final_error = 0;
  int adjusted = 0;
  double max_adjustment = 0;
};
LipmWalk lipm_walk(bool adjust, const Eigen::Vector2d& push, double t_push) {
  const testing::LipmWalkPlan plan(omega);
  const double dt = 1e-3;
  DcmStabilizerParameters sp;
  sp.omega = omega;
  DcmStabilizer stabilizer(sp);
  StepAdjustmentParameters ap;
  ap.enabled = adjust;
  ap.max_forward = 0.25;
  StepAdjustment step(ap);
  Eigen::Vector2d c = plan.placement[0], cd = omega * (plan.dcm(0) - plan.placement[0]);
  LipmWalk r;
  const int steps = static_cast<int>(std::lround(((plan.n - 1) * plan.T + 3) / dt));
  for (int i = 0; i < steps; ++i) {
    const double t = i * dt;
    const int k = plan.stance_of(t);
    const int stance = k % 2, swing = 1 - stance;
    std::array<StabilizerFoot, 2> feet;
    feet[stance].position.head<2>() = plan.placement[k] + step.foot_shift(stance);
    feet[stance].contact = true;
    feet[stance].force << 0, 0, 600;
    std::array<PlannedSwing, 2> swings;
    if (k < plan.n - 1)
      swings[swing] = {(t - k * plan.T) / plan.T, (k + 1) * plan.T};
    const Eigen::Vector2d target = plan.dcm(t) + step.dcm_shift();
    const Eigen::Vector2d xi = c + cd / omega;
    const double error = (xi - target).norm();
    r.max_error = std::max(r.max_error, std::min(error, 1.0));
    r.final_error = error;
    if (error > 1)
      break;
    stabilizer.update(xi, target, plan.placement[k] + step.zmp_shift(), feet, dt);
    const Eigen::Vector2d p = stabilizer.desired_zmp() - stabilizer.zmp_deficit();
    // As the balance loop feeds it: the DCM error about the stance sole's centre (here the ZMP
    // reference itself) beyond the sole's CoP region, in DCM units.
    const Eigen::Vector2d deficit =
        stabilizer.cop_excess(feet[stance], feet[stance].position.head<2>() + (xi - target));
    step.update(t, swings, straight, {false, false}, {step.landing_target(), step.landing_target()},
                deficit, omega, 1.0, dt);
    plan.lipm_step(c, cd, p, dt);
    if (std::abs(t + dt - t_push) < 0.5 * dt)
      cd += push;
  }
  r.adjusted = step.adjusted_steps();
  r.max_adjustment = step.max_adjustment();
  return r;
}

TEST(StepAdjustment, TheLipmWalkRecoversFromPushesTheAnkleCannotTake) {
  // Unpushed: the stabilizer tracks the exact reference; no landing moves.
  for (bool adjust : {false, true}) {
    const LipmWalk r = lipm_walk(adjust, Eigen::Vector2d::Zero(), -1);
    EXPECT_LT(r.max_error, 1e-9);
    EXPECT_EQ(r.adjusted, 0);
  }
  // Pushed in the third stance (right foot down, 1.6-2.4 s), 0.2 s before its end: the DCM
  // error jumps by dv / omega, past the sole's edge (0.1 m, 0.06 m) from its ZMP reference.
  struct Case {
    Eigen::Vector2d push;
    const char* name;
  };
  for (const Case& c : {Case{{0.45, 0}, "forward 0.45 m/s"}, Case{{-0.45, 0}, "backward"},
                        Case{{0, 0.3}, "sideways 0.3 m/s (left, the swing side)"}}) {
    const LipmWalk ankle = lipm_walk(false, c.push, 2.2);
    const LipmWalk stepping = lipm_walk(true, c.push, 2.2);
    std::printf("%s: ankle only max error %.3f m; stepping max %.3f m, final %.2e m, %d landings "
                "moved, largest %.3f m\n",
                c.name, ankle.max_error, stepping.max_error, stepping.final_error,
                stepping.adjusted, stepping.max_adjustment);
    EXPECT_GE(ankle.max_error, 1.0) << c.name; // diverged: a fall
    // The error never exceeds the push's own jump dv / omega.
    EXPECT_LT(stepping.max_error, 1.001 * c.push.norm() / omega) << c.name;
    EXPECT_LT(stepping.final_error, 1e-4) << c.name;
    EXPECT_GE(stepping.adjusted, 1) << c.name;
    EXPECT_GT(stepping.max_adjustment, 0.02) << c.name;
  }
}

} // namespace
} // namespace plantar::walking
