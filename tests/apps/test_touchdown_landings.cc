// Touchdowns with a planned velocity and their landing figures in a simulated walk (issue 23):
// two steps with rigid feet at Walking/Touchdown velocity = 0.2 m/s. The first landing is
// detected within a few ms of the planned touchdown, the swing sole comes down at about the
// planned speed, landings.csv holds the landings the summary counts. Scene-file errors of the
// new entries name the file, the parameter, the value and the range.
#include "apps/humanoid_simulation.h"
#include "humanoid_test_utilities.h"
#include "multibody/kinematics.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <stdexcept>
#include <string>

namespace plantar::app {
namespace {

using testing::load_humanoid_scene;

TEST(TouchdownLandings, TwoStepWalkLandsAtThePlannedVelocity) {
  const double v_touchdown = 0.2;
  const Scene scene =
      load_humanoid_scene("walk", {{"Robot/Foot form", "rigid"},
                                   {"Walking/Footsteps", "0.135, -0.105, 0; 0.135, 0.105, 0"},
                                   {"Walking/Standing before", "0.3"},
                                   {"Walking/Standing after", "0.5"},
                                   {"Walking/Touchdown velocity", "0.2"}});
  const walking::WalkingParameters& walk = scene.walking.walk;
  HumanoidSimulation sim(scene);
  const multibody::Model& model = sim.model();
  multibody::Data data(model);
  const int right = sim.foot_model().sole_frame(0);
  const double dt = scene.simulation.time_step;
  // Right sole height at every step (forward kinematics of the simulated state).
  std::vector<double> right_z;
  right_z.reserve(sim.n_steps() + 1);
  while (sim.steps_done() < sim.n_steps()) {
    sim.step();
    multibody::forward_kinematics(model, data, sim.q());
    right_z.push_back(multibody::frame_placement(model, data, right).translation.z());
  }
  const auto& s = sim.summary();
  const auto& landings_right = sim.landings(0);
  const auto& landings_left = sim.landings(1);
  // The feet also unload and land while the rigid robot rocks sideways during the 0.3 s of
  // standing of this shortened walk (landings at 0.09-0.26 s, in landings.csv): take each
  // foot's first landing after its planned lift-off.
  const double lift_off = walk.standing_before + walk.initial_double_support_time;
  const double planned = lift_off + walk.single_support_time;
  const double lift_off_left = planned + walk.double_support_time;
  const auto first_after = [](const std::vector<Landing>& landings, double t) {
    for (const Landing& l : landings)
      if (l.time > t)
        return &l;
    return static_cast<const Landing*>(nullptr);
  };
  const Landing* right_landing = first_after(landings_right, lift_off);
  const Landing* left_landing = first_after(landings_left, lift_off_left);
  ASSERT_NE(right_landing, nullptr);
  ASSERT_NE(left_landing, nullptr);
  const Landing& first = *right_landing;
  // The sole's vertical speed over the last step that ends before the touchdown (step n ends
  // at t = (n + 1) dt; right_z[n] is the sole height then).
  const int n_before = static_cast<int>(std::floor(first.time / dt - 1e-9)) - 1;
  ASSERT_GE(n_before, 1);
  const double speed = (right_z[n_before] - right_z[n_before - 1]) / dt;
  std::printf("left foot: planned touchdown %.4f s, detected %.4f s\n",
              lift_off_left + walk.single_support_time, left_landing->time);
  std::printf("right foot: planned touchdown %.4f s, detected %.4f s (%+.1f ms); sole speed "
              "before touchdown %.4f m/s (planned -%.2f, tol 20 %%); landing: impulse %.2f N s, "
              "peak %.0f N (weight %.0f N), rise time %.2f ms, filtered peak |a_z| %.2f m/s^2\n",
              planned, first.time, 1e3 * (first.time - planned), speed, v_touchdown, first.impulse,
              first.peak_force, s.robot_mass * 9.81, 1e3 * first.rise_time,
              first.peak_acceleration);
  std::printf("%d landings (right %zu, left %zu); max peak force %.0f N, max filtered |a_z| in "
              "a landing %.2f m/s^2; run: max |a_z| raw %.2f, filtered %.2f m/s^2\n",
              s.n_landings, landings_right.size(), landings_left.size(), s.max_landing_peak_force,
              s.max_landing_acceleration_z, s.max_waist_acceleration_z,
              s.max_waist_acceleration_z_filtered);
  // 5 ms: a few steps of tracking lag or of sag of the stance leg (1 mm is 5 ms at 0.2 m/s).
  EXPECT_NEAR(first.time, planned, 0.005);
  // 20 %: the plan is sampled every 5 ms and interpolated (its last sample's backward
  // difference is 4.5 % below v: walking_swing_height), plus the joint PD's tracking lag.
  EXPECT_NEAR(speed, -v_touchdown, 0.2 * v_touchdown);
  EXPECT_GT(first.peak_force, 0.01 * s.robot_mass * 9.81);
  EXPECT_EQ(s.n_landings, static_cast<int>(landings_right.size() + landings_left.size()));
  EXPECT_GE(s.max_landing_peak_force, first.peak_force);
  // The second step (left foot) lands 0.8 s later (single + double support).
  EXPECT_NEAR(left_landing->time, lift_off_left + walk.single_support_time, 0.005);

  // landings.csv: one row per landing; waist.csv: the filtered column.
  const std::filesystem::path dir =
      std::filesystem::temp_directory_path() / "plantar_test_touchdown_landings";
  std::filesystem::remove_all(dir);
  sim.write_csv(dir);
  std::ifstream in(dir / "landings.csv");
  ASSERT_TRUE(in.good());
  std::string line;
  int rows = -1;
  while (std::getline(in, line))
    ++rows;
  EXPECT_EQ(rows, s.n_landings);
  const TimeSeries& waist = sim.waist_series();
  const int az_filtered = waist.column("az_filtered");
  double max_filtered = 0;
  for (int r = 0; r < waist.n_rows(); ++r)
    max_filtered = std::max(max_filtered, std::abs(waist(r, az_filtered)));
  EXPECT_EQ(max_filtered, s.max_waist_acceleration_z_filtered);
  EXPECT_EQ(s.accelerometer_bandwidth, 100.0);
  std::filesystem::remove_all(dir);
}

TEST(TouchdownLandings, AccelerometerIsRawAtOrAboveNyquist) {
  // dt = 10 ms: the Nyquist frequency is 50 Hz, below the default 100 Hz: the samples hold no
  // frequency the filter would remove, so the raw a_z is used (cut-off 0 in the summary).
  const Scene scene = load_humanoid_scene("drop", {{"Robot/Foot form", "rigid"},
                                                   {"Simulation/Time step", "0.01"},
                                                   {"Simulation/Duration", "0.5"}});
  ASSERT_EQ(scene.output.accelerometer_bandwidth, 100.0);
  HumanoidSimulation sim(scene);
  sim.run();
  const auto& s = sim.summary();
  std::printf("dt = 10 ms: cut-off used %g Hz, max |a_z| raw %.4f, filtered %.4f m/s^2; %d "
              "landings\n",
              s.accelerometer_bandwidth, s.max_waist_acceleration_z,
              s.max_waist_acceleration_z_filtered, s.n_landings);
  EXPECT_EQ(s.accelerometer_bandwidth, 0.0);
  EXPECT_GT(s.max_waist_acceleration_z, 1.0);
  EXPECT_EQ(s.max_waist_acceleration_z_filtered, s.max_waist_acceleration_z);
}

/// Loads scenes/walk.prm with @p lines appended after an include; returns the error message.
std::string scene_error(const std::string& lines) {
  const std::filesystem::path file =
      std::filesystem::temp_directory_path() / "plantar_test_touchdown_bad.prm";
  {
    std::ofstream out(file);
    out << "include " << PLANTAR_SOURCE_DIR << "/scenes/walk.prm\n" << lines;
  }
  dealii::ParameterHandler prm;
  try {
    load_scene(file, prm);
  } catch (const std::exception& e) {
    std::filesystem::remove(file);
    return e.what();
  }
  std::filesystem::remove(file);
  return "";
}

TEST(TouchdownLandings, BadSceneValuesAreReported) {
  struct Case {
    const char* lines;
    std::vector<const char*> expected;
  };
  const Case cases[] = {
      {"subsection Walking\n  set Touchdown velocity = 1.5\nend\n",
       {"plantar_test_touchdown_bad.prm", "Touchdown velocity", "1.5", "0...1"}},
      {"subsection Walking\n  set Touchdown velocity = 0.5\n  set Step height = 0.01\nend\n",
       {"plantar_test_touchdown_bad.prm", "touchdown_velocity = 0.5", "[0, 0.24359"}},
      {"subsection Output\n  set Accelerometer bandwidth = 2e4\nend\n",
       {"plantar_test_touchdown_bad.prm", "Accelerometer bandwidth", "2e4", "0...10000"}},
      {"subsection Output\n  set Landing window = 0\nend\n",
       {"plantar_test_touchdown_bad.prm", "Output/Landing window = 0", "(0, 1] s"}},
  };
  for (const Case& c : cases) {
    const std::string what = scene_error(c.lines);
    std::printf("%s-> %s\n", c.lines, what.c_str());
    for (const char* part : c.expected)
      EXPECT_NE(what.find(part), std::string::npos) << "'" << part << "' not in: " << what;
  }
}

} // namespace
} // namespace plantar::app
