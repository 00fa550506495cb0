// The paper's six-step walk (slow), in the three foot forms of scenes/walk.prm: the walk
// completes without falling (the simulation throws on a fall), the waist stays within 5 cm
// of its planned height, both feet end within 2 cm of their planned final positions (issue
// 5). The paper's figures (max waist z acceleration, lean inclination difference) are printed
// with their dt. The full lean runs in the three foot forms.
#include "apps/humanoid_simulation.h"
#include "humanoid_test_utilities.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

namespace plantar::app {
namespace {

class HumanoidFull : public ::testing::TestWithParam<const char*> {};

TEST_P(HumanoidFull, SixStepWalk) {
  const char* const form = GetParam();
  const Scene scene = testing::load_humanoid_scene("walk", {{"Robot/Foot form", form}});
  HumanoidSimulation sim(scene);
  sim.run();
  const auto& s = sim.summary();
  // Distances in 3-D (the fem sole's planned soles are lifted by its thickness).
  const double right = (s.final_right_sole - s.planned_right_sole).norm();
  const double left = (s.final_left_sole - s.planned_left_sole).norm();
  // The paper's criterion: the waist z acceleration during the walk proper (t in [1, 7] s).
  const auto& w = sim.waist_series();
  double peak = 0;
  for (int r = 0; r < w.n_rows(); ++r)
    if (w(r, 0) >= 1.0 && w(r, 0) <= 7.0)
      peak = std::max(peak, std::abs(w(r, w.column("az"))));
  std::printf("six-step walk (%s), dt %.4g s: %d steps, loop %.1f s (%.2f s per simulated s); "
              "waist max |z - z_ref| %.4f m (tol 0.05); right sole error %.4f m, left %.4f m "
              "(tol 0.02); final right (%.4f, %.4f) planned (%.4f, %.4f); max |a_z| during the "
              "walk %.2f m/s^2; %d unconverged solves\n",
              form, s.time_step, s.n_steps, s.loop_wall_time, s.cost(), s.max_waist_height_error,
              right, left, s.final_right_sole.x(), s.final_right_sole.y(), s.planned_right_sole.x(),
              s.planned_right_sole.y(), peak, s.n_unconverged);
  EXPECT_NEAR(s.simulated_time, 8.0, 1e-9); // the whole walk and the final standing second
  EXPECT_NEAR(s.planned_right_sole.x(), 0.675, 1e-9);
  EXPECT_NEAR(s.planned_left_sole.x(), 0.675, 1e-9);
  EXPECT_LT(s.max_waist_height_error, 0.05);
  EXPECT_LT(right, 0.02);
  EXPECT_LT(left, 0.02);
}

TEST_P(HumanoidFull, FullLean) {
  const Scene scene = testing::load_humanoid_scene("lean", {{"Robot/Foot form", GetParam()}});
  HumanoidSimulation sim(scene);
  sim.run();
  const auto& s = sim.summary();
  const double deg = 180 / M_PI;
  std::printf("lean (%s), dt %.4g s: commanded %.4f deg, measured %.4f deg, difference %.4f deg "
              "(tol 2 deg)\n",
              GetParam(), s.time_step, s.commanded_roll * deg, s.final_roll * deg,
              (s.commanded_roll - s.final_roll) * deg);
  EXPECT_NEAR(s.commanded_roll * deg, 14.3, 1e-6);
  EXPECT_NEAR(s.final_roll * deg, 14.3, 2.0);
}

INSTANTIATE_TEST_SUITE_P(FootForms, HumanoidFull, ::testing::ValuesIn(testing::foot_forms),
                         [](const auto& info) {
                           std::string name = info.param;
                           for (auto& c : name)
                             if (c == ' ')
                               c = '_';
                           return name;
                         });

} // namespace
} // namespace plantar::app
