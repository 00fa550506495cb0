// Touchdown adaptation (multibody/walking/touchdown_adaptation.h) on a swing foot that tracks its
// reference exactly, over a stiff ground (f = k max(0, -gap)) higher or lower than planned.
#include "multibody/walking/footstep_plan.h"
#include "multibody/walking/touchdown_adaptation.h"

#include <algorithm>
#include <cstdio>
#include <gtest/gtest.h>

namespace {

using namespace plantar::walking;

struct SwingResult {
  double level = 0, max_penetration = 0, final_gap = 0;
  double max_descent = 0; ///< largest planned descent in one step (m)
  int early = 0, late = 0;
};

/// @p swings swings of the default walk's profile (0.1 m/s touchdown), each followed by 0.3 s
/// planned down. The right foot starts on its planned ground; from the apex of its first swing
/// on, the ground is @p ground_offset above (> 0: an unplanned step up) or below its plan. The
/// left foot stays down on its planned ground. Stiffness k = 1e6 N/m, dt = 1 ms.
SwingResult run_swings(double ground_offset, int swings) {
  WalkingParameters walk;
  walk.touchdown_velocity = 0.1;
  TouchdownParameters p;
  p.enabled = true;
  TouchdownAdaptation adaptation(p);
  const double dt = 1e-3, k = 1e6, stance = 800;
  SwingResult r;
  Eigen::Vector2d dz = Eigen::Vector2d::Zero();
  double ground = 0.0;
  auto step = [&](double h) {
    const double gap = h + dz[0] - ground; // the foot exactly on its adapted reference
    r.max_penetration = std::max(r.max_penetration, -gap);
    r.final_gap = gap;
    const Eigen::Vector2d force(k * std::max(0.0, -gap), stance);
    dz = adaptation.update(Eigen::Vector2d(h, 0.0), force, dt);
  };
  const int n_swing = static_cast<int>(walk.single_support_time / dt);
  for (int s = 0; s < swings; ++s) {
    for (int i = 1; i <= n_swing; ++i) {
      if (2 * i >= n_swing)
        ground = ground_offset; // past the edge
      const double h = swing_foot_height(walk, double(i) / n_swing)(0);
      r.max_descent =
          std::max(r.max_descent, swing_foot_height(walk, double(i - 1) / n_swing)(0) - h);
      step(h);
    }
    for (int i = 0; i < 300; ++i)
      step(0.0);
  }
  r.level = adaptation.levels()[0];
  r.early = adaptation.early_touchdowns();
  r.late = adaptation.late_touchdowns();
  EXPECT_EQ(adaptation.levels()[1], 0.0); // the stance foot is never moved
  return r;
}

TEST(TouchdownAdaptation, EarlyTouchdownOnAnUnplannedStep) {
  // The first swing leaves the lower level and meets the step at touchdown; the second starts
  // and lands on the step.
  for (const double rise : {0.02, 0.04}) {
    const SwingResult r = run_swings(rise, 2);
    std::printf("step %.3f m: level %.6f m, penetration %.2e m, final gap %.1e m, early %d, late "
                "%d\n",
                rise, r.level, r.max_penetration, r.final_gap, r.early, r.late);
    // Found within two steps of the descent (the step the contact happens in and the control
    // period the offset takes to act) plus the detection force's penetration f_td / k.
    const double bound = 2 * r.max_descent + 50.0 / 1e6;
    std::printf("  bound: 2 x largest descent per step %.2e m + f_td / k 5e-5 m\n", r.max_descent);
    EXPECT_NEAR(r.level, rise, bound);
    EXPECT_LT(r.max_penetration, bound);
    EXPECT_LT(std::abs(r.final_gap), bound);
    EXPECT_GE(r.early, 1);
  }
}

TEST(TouchdownAdaptation, LateTouchdownSearchesDown) {
  const SwingResult r = run_swings(-0.01, 1);
  std::printf("1 cm lower: level %.6f m, penetration %.2e m, final gap %.1e m, early %d, late "
              "%d\n",
              r.level, r.max_penetration, r.final_gap, r.early, r.late);
  // Found within one search step (0.1 m/s x 1 ms) plus the detection force's f_td / k.
  EXPECT_NEAR(r.level, -0.01, 1.5e-4);
  EXPECT_LT(std::abs(r.final_gap), 1.5e-4);
  EXPECT_EQ(r.late, 1);
  EXPECT_EQ(r.early, 0);
}

TEST(TouchdownAdaptation, PlannedGroundIsLeftAlone) {
  const SwingResult r = run_swings(0.0, 3);
  std::printf("planned ground: level %.2e m, penetration %.2e m\n", r.level, r.max_penetration);
  // A foot landing on its plan unloaded searches one step (0.1 mm) at most: the level stays
  // within v_s dt + f_td / k and does not drift over the swings.
  EXPECT_LT(std::abs(r.level), 1.5e-4);
  EXPECT_LT(r.max_penetration, 1.5e-4);
}

TEST(TouchdownAdaptation, DisabledDoesNothingAndBadInputIsReported) {
  TouchdownAdaptation off;
  const Eigen::Vector2d dz =
      off.update(Eigen::Vector2d(0.05, 0.0), Eigen::Vector2d(1000.0, 1000.0), 1e-3);
  EXPECT_EQ(dz, Eigen::Vector2d::Zero());
  TouchdownParameters bad;
  bad.force = 0;
  EXPECT_THROW(TouchdownAdaptation{bad}, std::invalid_argument);
}

} // namespace
