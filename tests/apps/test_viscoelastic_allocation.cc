// The humanoid time loop with viscoelastic soles (law=prony, issue 24) allocates nothing:
// every operator new of the process is counted (global replacement in this test) while
// HumanoidSimulation::step() runs, during standing and during the first steps of a walk
// (a swing sole lifted, recovering and landing again). As tests/apps/test_humanoid_allocation.cc
// for the other foot forms.
#include "apps/humanoid_simulation.h"
#include "tests/allocation_counter.h"
#include "tests/apps/humanoid_test_utilities.h"

#include <gtest/gtest.h>

#include <cstdio>

namespace plantar::app {
namespace {

TEST(ViscoelasticAllocation, StepAllocatesNothing) {
  for (const char* type : {"stand", "walk"}) {
    const Scene scene = testing::load_humanoid_scene(
        type, {{"Robot/Foot form", "fem sole"},
               {"Sole/Materials", "rubber: law=prony, E=2e6, nu=0.3, E1=2e6, tau1=4.5e-3"},
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
    std::printf(
        "%s (viscoelastic sole): %d steps, %ld heap allocations in step() (expected 0); up to %d "
        "contacts; the counter saw the one deliberate allocation: %s\n",
        type, sim.steps_done() - 10, n, sim.summary().max_active_contacts,
        count.counter_works ? "yes" : "no");
    EXPECT_TRUE(count.counter_works);
    EXPECT_EQ(n, 0);
    EXPECT_GT(sim.summary().sole_dissipated_energy, 0.0);
  }
}

} // namespace
} // namespace plantar::app
