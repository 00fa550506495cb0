// Hard cases of issue 8 at the humanoid level (apps::HumanoidSimulation, scenes/drop.prm with
// overrides), see docs/stability.md:
// - drop from 10 cm in the three foot forms: the waist reaches sqrt(2 g h) (2 %) before the
//   impact, every solve stays below Contact/Failure residual (else the run stops), the deepest
//   contact point stays within Simulation/Max penetration, the weight is carried at the end (1 %);
//   the same on the Kelvin-Voigt sole with the theta = 1/2 stepper;
// - a known-impossible solver setting (one iteration, residual bound 1e-12) stops the run with
//   an error naming the step and time of the first contact, sqrt(2 h / g) after the release.
#include "apps/humanoid_simulation.h"
#include "humanoid_test_utilities.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <regex>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

namespace plantar::app {
namespace {

using testing::load_humanoid_scene;

constexpr double g = 9.81;

class HardScenes : public ::testing::TestWithParam<const char*> {};

/// The 10 cm drop checks with @p overrides of scenes/drop.prm (@p label in the printout).
void drop_from_ten_centimetres(const std::vector<std::pair<std::string, std::string>>& overrides,
                               const char* label) {
  const double h = 0.1;
  const Scene scene = load_humanoid_scene("drop", overrides);
  HumanoidSimulation sim(scene);
  sim.run();
  const auto& s = sim.summary();
  const auto& w = sim.waist_series();
  double impact_speed = 0;
  for (int row = 0; row < s.n_steps; ++row)
    impact_speed = std::max(impact_speed, -w(row, w.column("vz")));
  const double weight = sim.model().total_mass() * g;
  std::printf("drop 10 cm (%s): dt %.4g s, %d steps, loop %.1f s; max waist speed %.4f m/s vs "
              "sqrt(2 g h) = %.4f m/s (tol 2 %%); max |a_z| %.1f m/s^2; %d of %d solves above "
              "tolerance, max residual %.2e m/s (failure bound %.1e); max iterations %d; max "
              "penetration %.3f mm (bound %.1f mm); final force %.2f N vs m g %.2f N\n",
              label, s.time_step, s.n_steps, s.loop_wall_time, impact_speed, std::sqrt(2 * g * h),
              s.max_waist_acceleration_z, s.n_unconverged, s.n_solves, s.max_solver_residual,
              scene.contact.failure_residual, s.max_solver_iterations, s.max_penetration * 1e3,
              scene.simulation.max_penetration * 1e3, s.final_contact_force.z(), weight);
  EXPECT_NEAR(impact_speed / std::sqrt(2 * g * h), 1.0, 0.02);
  EXPECT_LE(s.max_solver_residual, scene.contact.failure_residual);
  EXPECT_LE(s.max_penetration, scene.simulation.max_penetration);
  EXPECT_TRUE(std::isfinite(s.max_waist_acceleration_z));
  EXPECT_NEAR(s.final_contact_force.z() / weight, 1.0, 0.01);
}

TEST_P(HardScenes, DropFromTenCentimetres) {
  drop_from_ten_centimetres({{"Robot/Foot form", GetParam()}, {"Simulation/Release height", "0.1"}},
                            GetParam());
}

// The theta = 1/2 stepper (no numerical damping) on the Kelvin-Voigt sole of
// bench/work_precision/walk_damped_fast.prm.
TEST(HardScenesTheta, DropFromTenCentimetresThetaHalfDampedSole) {
  drop_from_ten_centimetres({{"Robot/Foot form", "fem sole"},
                             {"Simulation/Release height", "0.1"},
                             {"Simulation/Theta", "0.5"},
                             {"Sole/Damping time", "0.001"},
                             {"Simulation/Duration", "2"}}, // less damped: settles later
                            "fem sole, theta 1/2, damping 1 ms");
}

INSTANTIATE_TEST_SUITE_P(FootForms, HardScenes, ::testing::ValuesIn(testing::foot_forms),
                         [](const auto& info) {
                           std::string name = info.param;
                           for (char& c : name)
                             if (c == ' ')
                               c = '_';
                           return name;
                         });

TEST(HardSceneFailures, ImpossibleSolverSettingStopsWithStepAndTime) {
  const double h = 0.01;
  const Scene scene = load_humanoid_scene("drop", {{"Contact/Max iterations", "1"},
                                                   {"Contact/Tolerance", "1e-12"},
                                                   {"Contact/Failure residual", "1e-12"},
                                                   // the direct solve meets 1e-12 when it
                                                   // applies: the iteration must fail
                                                   {"Contact/Sticking direct solve", "false"}});
  HumanoidSimulation sim(scene);
  try {
    sim.run();
    ADD_FAILURE() << "the run did not stop";
  } catch (const std::runtime_error& e) {
    const std::string what = e.what();
    std::printf("expected failure: %s\n", what.c_str());
    std::smatch match;
    ASSERT_TRUE(std::regex_search(what, match,
                                  std::regex("step ([0-9]+), t = ([0-9.e-]+) s: "
                                             "contact solver max_iterations")))
        << what;
    const int step = std::stoi(match[1]);
    const double t = std::stod(match[2]);
    // The first contact solve: the feet reach the ground sqrt(2 h / g) = 45 ms after release.
    const double t_contact = std::sqrt(2 * h / g), dt = scene.simulation.time_step;
    std::printf("failed at step %d, t = %.4f s; first contact expected at %.4f s (tol 3 dt)\n",
                step, t, t_contact);
    EXPECT_NEAR(t, step * dt, 1e-12);
    EXPECT_NEAR(t, t_contact, 3 * dt);
  }
}

} // namespace
} // namespace plantar::app
