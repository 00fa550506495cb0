// The hyperelastic (Neo-Hookean) sole against the linear sole of the same small-strain E, nu
// in the humanoid drop scene (scenes/drop_nonlinear.prm, 0.3 s, dt = 1 ms). Reference: the
// linear sole's run. As E grows the strains shrink, so the two models must agree better:
// the differences of the waist's peak |a_z| and of its lowest height decrease monotonically
// with E, are within 10 % at 1 MPa and 1 % at 10 MPa, and the soft sole does re-condense.
#include "apps/humanoid_simulation.h"
#include "tests/apps/humanoid_test_utilities.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <string>

namespace plantar::app {
namespace {

HumanoidSummary drop(double young, bool hyperelastic) {
  const std::string e = std::to_string(young);
  const Scene scene = testing::load_humanoid_scene(
      "drop_nonlinear",
      {{"Simulation/Duration", "0.3"},
       {"Output/Write CSV", "false"},
       {"Output/Write VTU", "false"},
       {"Sole/Model", hyperelastic ? "hyperelastic" : "linear"},
       {"Sole/Materials", "rubber: law=" + std::string(hyperelastic ? "neo_hookean" : "linear") +
                              ", E=" + e + ", nu=0.3"}});
  HumanoidSimulation simulation(scene);
  simulation.run();
  return simulation.summary();
}

TEST(NonlinearScenes, DropDifferencesShrinkWithStiffness) {
  const double youngs[] = {1e6, 4e6, 10e6};
  double previous_acceleration = 1e9, previous_height = 1e9;
  for (const double young : youngs) {
    const HumanoidSummary linear = drop(young, false);
    const HumanoidSummary nonlinear = drop(young, true);
    const double acceleration =
        std::abs(nonlinear.max_waist_acceleration_z - linear.max_waist_acceleration_z) /
        linear.max_waist_acceleration_z;
    const double height = std::abs(nonlinear.min_waist_height - linear.min_waist_height);
    std::printf("E = %.0e Pa: peak |a_z| linear %.3f, hyperelastic %.3f m/s^2 (rel. diff "
                "%.2e); lowest waist %.6f vs %.6f m (diff %.2e m); %d re-condensations, "
                "%d Newton checks\n",
                young, linear.max_waist_acceleration_z, nonlinear.max_waist_acceleration_z,
                acceleration, linear.min_waist_height, nonlinear.min_waist_height, height,
                nonlinear.sole_recondensations, nonlinear.sole_newton_checks);
    EXPECT_LE(acceleration, previous_acceleration + 1e-12) << "E = " << young;
    EXPECT_LE(height, previous_height + 1e-12) << "E = " << young;
    previous_acceleration = acceleration;
    previous_height = height;
    if (young == 1e6) {
      EXPECT_LT(acceleration, 0.10);
      EXPECT_GT(nonlinear.sole_recondensations, 0);
    }
    if (young == 10e6) {
      EXPECT_LT(acceleration, 0.01);
    }
  }
}

} // namespace
} // namespace plantar::app
