// The second humanoid, kestrel (models/kestrel, docs/kestrel_model.md; issue 29), in the
// stand, drop, lean and six-step walk scenes (scenes/kestrel/) in the three foot forms. Its
// legs have no closed-form IK (numerical SE(3) IK), its soles are placed on the foot links by
// the scene. Checked against independent figures as for HRP-2 (test_humanoid_scenes.cc):
// stand: the ground carries m g (m from the URDF) and the waist stays within 1 mm;
// drop:  free fall a_z = -g before the impact, m g carried at the end;
// lean:  the commanded roll reached, the measured one within 2 deg;
// walk:  no fall, the waist within 5 cm of its planned height, both feet within 2 cm of their
//        planned final places (the plan: the last footsteps of scenes/kestrel/kestrel.prm).
#include "apps/humanoid_simulation.h"
#include "humanoid_test_utilities.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

namespace plantar::app {
namespace {

using testing::load_humanoid_scene;

class Kestrel : public ::testing::TestWithParam<const char*> {};

TEST_P(Kestrel, Stands) {
  HumanoidSimulation sim(load_humanoid_scene("kestrel/stand", {{"Robot/Foot form", GetParam()}}));
  sim.run();
  const auto& s = sim.summary();
  const double weight = sim.model().total_mass() * 9.81;
  std::printf("kestrel stand (%s): waist moved %.2e mm after settling (tol 1 mm); ground force "
              "z %.3f N vs m g %.3f N; horizontal %.2e N\n",
              GetParam(), s.stand_window_deviation * 1e3, s.final_contact_force.z(), weight,
              s.final_contact_force.head<2>().norm());
  EXPECT_NEAR(sim.model().total_mass(), 40.0, 1e-9); // docs/kestrel_model.md
  EXPECT_LT(s.stand_window_deviation, 1e-3);
  EXPECT_NEAR(s.final_contact_force.z() / weight, 1.0, 1e-2);
  EXPECT_LT(s.final_contact_force.head<2>().norm(), 1e-2 * weight);
}

TEST_P(Kestrel, Drops) {
  HumanoidSimulation sim(load_humanoid_scene("kestrel/drop", {{"Robot/Foot form", GetParam()}}));
  sim.run();
  const auto& s = sim.summary();
  const auto& w = sim.waist_series();
  const double az = w(9, w.column("az")); // t = 10 ms: free fall (1 cm lasts 45 ms)
  const double weight = sim.model().total_mass() * 9.81;
  std::printf("kestrel drop (%s): a_z at 10 ms %.4f m/s^2 (-g, tol 2 %%); max |a_z| %.2f m/s^2; "
              "final ground force %.3f N vs m g %.3f N (tol 1 %%)\n",
              GetParam(), az, s.max_waist_acceleration_z, s.final_contact_force.z(), weight);
  EXPECT_NEAR(az, -9.81, 0.02 * 9.81);
  EXPECT_GT(s.max_waist_acceleration_z, 9.81);
  EXPECT_NEAR(s.final_contact_force.z() / weight, 1.0, 1e-2);
}

TEST_P(Kestrel, Leans) {
  HumanoidSimulation sim(load_humanoid_scene("kestrel/lean", {{"Robot/Foot form", GetParam()}}));
  sim.run();
  const auto& s = sim.summary();
  const double deg = 180 / M_PI;
  std::printf("kestrel lean (%s): commanded %.4f deg, measured %.4f deg (tol 2 deg)\n", GetParam(),
              s.commanded_roll * deg, s.final_roll * deg);
  EXPECT_NEAR(s.commanded_roll * deg, 14.3, 1e-6);
  EXPECT_NEAR(s.final_roll * deg, 14.3, 2.0);
}

TEST_P(Kestrel, WalksSixSteps) {
  HumanoidSimulation sim(load_humanoid_scene("kestrel/walk", {{"Robot/Foot form", GetParam()}}));
  sim.run();
  const auto& s = sim.summary();
  const double right = (s.final_right_sole - s.planned_right_sole).head<2>().norm();
  const double left = (s.final_left_sole - s.planned_left_sole).head<2>().norm();
  std::printf("kestrel walk (%s): %d steps, waist max |z - z_ref| %.4f m (tol 0.05); feet end "
              "%.4f and %.4f m from their plan (tol 0.02); max |a_z| %.2f m/s^2; %d unconverged "
              "solves, max residual %.1e m/s\n",
              GetParam(), s.n_steps, s.max_waist_height_error, right, left,
              s.max_waist_acceleration_z, s.n_unconverged, s.max_solver_residual);
  EXPECT_EQ(s.n_steps, sim.n_steps());
  EXPECT_NEAR(s.planned_right_sole.x(), 0.5, 1e-9);
  EXPECT_NEAR(s.planned_left_sole.y(), 0.08, 1e-9);
  EXPECT_LT(s.max_waist_height_error, 0.05);
  EXPECT_LT(right, 0.02);
  EXPECT_LT(left, 0.02);
}

INSTANTIATE_TEST_SUITE_P(FootForms, Kestrel, ::testing::ValuesIn(testing::foot_forms),
                         testing::foot_form_name<::testing::TestParamInfo<const char*>>);

} // namespace
} // namespace plantar::app
