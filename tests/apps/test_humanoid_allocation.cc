// The humanoid time loop allocates nothing: every operator new of the process is counted
// (global replacement in this test) while HumanoidSimulation::step() runs, for each foot
// form, during standing and during the first steps of a walk (swing foot lifting and
// landing patches included).
#include "apps/humanoid_simulation.h"
#include "tests/allocation_counter.h"
#include "tests/apps/humanoid_test_utilities.h"

#include <gtest/gtest.h>

#include <cstdio>

namespace plantar::app {
namespace {

class HumanoidAllocation : public ::testing::TestWithParam<const char*> {};

TEST_P(HumanoidAllocation, StepAllocatesNothing) {
  for (const char* type : {"stand", "walk"}) {
    const Scene scene = testing::load_humanoid_scene(
        type, {{"Robot/Foot form", GetParam()},
               {"Simulation/Duration", "1.6"},
               {"Walking/Footsteps", "0.135, -0.105, 0; 0.135, 0.105, 0"},
               {"Walking/Standing before", "0.1"},
               {"Walking/Initial double support time", "0.4"},
               // The compensation (set-up only) of this 0.1 s start asks the ankle roll for
               // 0.84 rad, past its limit, which the leg IK now refuses.
               {"Robot/Ankle deflection compensation", "false"},
               // This abrupt start tips the walk past the default 20 deg at 1.2-1.6 s; the
               // count is of the step's code paths, fallen or not.
               {"Simulation/Fall tilt", "90"}});
    HumanoidSimulation sim(scene);
    for (int n = 0; n < 10; ++n)
      sim.step();
    const auto count = plantar::testing::count_allocations([&] {
      while (sim.steps_done() < sim.n_steps())
        sim.step();
    });
    const long n = count.during;
    std::printf("%s (%s): %d steps, %ld heap allocations in step() (expected 0); up to %d "
                "contacts; the counter saw the one deliberate allocation: %s\n",
                type, GetParam(), sim.steps_done() - 10, n, sim.summary().max_active_contacts,
                count.counter_works ? "yes" : "no");
    EXPECT_TRUE(count.counter_works);
    EXPECT_EQ(n, 0);
  }
}

INSTANTIATE_TEST_SUITE_P(FootForms, HumanoidAllocation, ::testing::ValuesIn(testing::foot_forms),
                         [](const auto& info) {
                           std::string name = info.param;
                           for (auto& c : name)
                             if (c == ' ')
                               c = '_';
                           return name;
                         });

} // namespace
} // namespace plantar::app
