// The sensor-based stabilizer in the humanoid scenes (issue 23, docs/stabilizer.md):
// - push recovery (scenes/push_stand.prm): 30 N s on the waist; without the stabilizer the
//   robot falls, with it the robot recovers and its DCM returns to the reference;
// - the kinematic CoM/DCM estimate against the simulator's ground truth on the six-step walk;
// - the six-step walk with the stabilizer completes in the three foot forms, the soles at
//   their planned positions;
// - step adjustment (multibody/walking/step_adjustment.h): the rigid walk pushed forward in
//   its third single support by 40 N s (sideways by 30 N s) falls with the ankle strategy alone
//   and completes when the landings move; unpushed, turning it on changes nothing (bit for bit);
// - step timing (multibody/walking/step_timing.h): pushed sideways by 40 N s, the walk falls
//   with step adjustment alone and completes when the swings also land earlier; unpushed,
//   turning it on changes nothing (bit for bit);
// - Stabilizer = none is the PD playback bit for bit: the first 2 s of the rigid walk's waist
//   series equal (==, 17 digits) those recorded by `plantar run` with Stabilizer = none
//   (tests/apps/data/walk_rigid_2s_waist_tree.csv), sensor noise set or not. The recording
//   was first made by the commit before the stabilizer (66393ee) and re-made when the tree
//   factorisation of M_eff (multibody/tree_factorization.h) changed the round-off.
#include "apps/humanoid_job.h"
#include "apps/humanoid_simulation.h"
#include "tests/allocation_counter.h"
#include "tests/apps/humanoid_test_utilities.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

namespace plantar::app {
namespace {

/// Rows of a CSV file of numbers (header skipped), parsed with strtod (exact for 17 digits).
std::vector<std::vector<double>> read_numbers(const std::string& path) {
  std::ifstream in(path);
  std::vector<std::vector<double>> rows;
  std::string line;
  std::getline(in, line);
  while (std::getline(in, line)) {
    std::vector<double> row;
    std::stringstream items(line);
    std::string item;
    while (std::getline(items, item, ','))
      row.push_back(std::strtod(item.c_str(), nullptr));
    rows.push_back(row);
  }
  return rows;
}

/// Entries of two series that are not equal (==), or -1 if their sizes differ.
int differing_entries(const TimeSeries& a, const TimeSeries& b) {
  if (a.n_rows() != b.n_rows() || a.n_columns() != b.n_columns())
    return -1;
  int differing = 0;
  for (int i = 0; i < a.n_rows(); ++i)
    for (int j = 0; j < a.n_columns(); ++j)
      differing += a(i, j) == b(i, j) ? 0 : 1;
  return differing;
}

/// The default walk on rigid feet at dt = 1 ms, theta = 1, touchdown adaptation on, pushed on
/// the waist along @p direction by @p impulse (N s over 0.1 s from t = 3.5 s, in the third
/// single support: the right foot swings, 0.48 s before its planned touchdown).
std::vector<std::pair<std::string, std::string>>
pushed_walk(double impulse, bool adjust, const char* direction = "1, 0, 0", bool timing = false) {
  return {{"Robot/Foot form", "rigid"},
          // the stiff walk's foot damping (2000 N m s/rad) and exact F/T readings
          {"Control/Foot damping rate", "0"},
          {"Control/Force sensor bandwidth", "0"},
          {"Simulation/Time step", "0.001"},
          {"Simulation/Theta", "1"},
          {"Control/Touchdown adaptation", "true"},
          {"Control/Step adjustment", adjust ? "true" : "false"},
          {"Control/Step timing", timing ? "true" : "false"},
          {"Simulation/Push time", "3.5"},
          {"Simulation/Push direction", direction},
          {"Simulation/Push magnitude", std::to_string(impulse)},
          {"Simulation/Push duration", "0.1"}};
}

TEST(StabilizerNone, IsThePdPlaybackBitForBit) {
  const auto recorded = read_numbers(std::string(PLANTAR_SOURCE_DIR) +
                                     "/tests/apps/data/walk_rigid_2s_waist_tree.csv");
  ASSERT_EQ(recorded.size(), 200u);
  for (const bool noisy_sensors : {false, true}) {
    std::vector<std::pair<std::string, std::string>> overrides{
        {"Robot/Foot form", "rigid"},
        {"Simulation/Duration", "2"},
        {"Output/Output every", "10"},
        {"Control/Stabilizer", "none"},
        // as recorded: no direct solve
        // for rigid contacts then
        {"Contact/Sticking direct solve", "false"}};
    if (noisy_sensors)
      overrides.insert(overrides.end(), {{"Control/Force noise", "5"},
                                         {"Control/Sensor delay", "3"},
                                         {"Control/State estimate", "ground truth"}});
    HumanoidSimulation sim(testing::load_humanoid_scene("walk", overrides));
    sim.run();
    const TimeSeries& waist = sim.waist_series();
    ASSERT_EQ(waist.n_rows(), 200);
    // The recorded columns (t ... z_ref); later columns (az_filtered) are newer than it.
    const int columns = static_cast<int>(recorded[0].size());
    ASSERT_GE(waist.n_columns(), columns);
    int differing = 0;
    for (int i = 0; i < waist.n_rows(); ++i)
      for (int j = 0; j < columns; ++j)
        differing += waist(i, j) == recorded[i][j] ? 0 : 1;
    std::printf("Stabilizer = none%s: %d of %d waist values differ from the recording\n",
                noisy_sensors ? " (sensor noise, delay, ground truth set)" : "", differing,
                waist.n_rows() * columns);
    EXPECT_EQ(differing, 0);
  }
}

TEST(PushRecovery, FallsWithoutTheStabilizerAndRecoversWithIt) {
  HumanoidSimulation playback(
      testing::load_humanoid_scene("push_stand", {{"Control/Stabilizer", "none"}}));
  const std::string failure = testing::run_to_stop(playback);
  std::printf("Stabilizer = none: %s\n", failure.c_str());
  EXPECT_NE(failure.find("the robot fell"), std::string::npos) << failure;

  HumanoidSimulation stabilized(testing::load_humanoid_scene("push_stand", {}));
  ASSERT_NO_THROW(stabilized.run());
  const walking::BalanceController* balance = stabilized.balance();
  ASSERT_NE(balance, nullptr);
  const walking::BalanceStatistics& s = balance->statistics();
  const HumanoidSummary& summary = stabilized.summary();
  std::printf("Stabilizer = dcm: completed; max DCM error %.4f m, final true DCM error (%.2e, "
              "%.2e) m, min waist height %.4f m, final soles x %.5f %.5f m\n",
              s.max_dcm_error, s.true_dcm_error.x(), s.true_dcm_error.y(), summary.min_waist_height,
              summary.final_right_sole.x(), summary.final_left_sole.x());
  // The push moved the DCM by several centimetres (more than the standing offset) ...
  EXPECT_GT(s.max_dcm_error, 0.05);
  // ... and 2 s later it is back within 2 cm of the reference, the feet where they were.
  EXPECT_LT(s.true_dcm_error.norm(), 0.02);
  EXPECT_LT(std::abs(summary.final_right_sole.x()), 0.005);
  EXPECT_LT(std::abs(summary.final_left_sole.x()), 0.005);
}

TEST(PushRecovery, AWaistTiltedPastFallTiltIsAFall) {
  // The push without the stabilizer, Fall height out of the way: the robot tips over with its
  // waist still high, and the run stops on the tilt of the waist's z axis from the upright
  // reference's. Independent of the check: the tilt from the recorded Euler angles (waist.csv,
  // every step; ZYX: R_zz = cos(pitch) cos(roll)).
  HumanoidSimulation sim(testing::load_humanoid_scene(
      "push_stand", {{"Control/Stabilizer", "none"}, {"Simulation/Fall height", "0"}}));
  const std::string failure = testing::run_to_stop(sim);
  std::printf("%s\n", failure.c_str());
  const std::string tilted = "waist tilted ";
  ASSERT_NE(failure.find(tilted), std::string::npos) << failure;
  EXPECT_NE(failure.find("Simulation/Fall tilt 20 deg"), std::string::npos) << failure;
  const double stopped_at = std::stod(failure.substr(failure.find(tilted) + tilted.size()));
  const TimeSeries& waist = sim.waist_series();
  ASSERT_GT(waist.n_rows(), 2);
  const int roll = 10, pitch = 11; // columns of waist.csv
  double largest = 0;
  for (int i = 0; i < waist.n_rows(); ++i)
    largest = std::max(largest, std::acos(std::cos(waist(i, pitch)) * std::cos(waist(i, roll))));
  const double last = std::acos(std::cos(waist(waist.n_rows() - 1, pitch)) *
                                std::cos(waist(waist.n_rows() - 1, roll)));
  const double deg = 180 / M_PI;
  std::printf("tilt: %.3f deg at the last recorded step, %.3f deg at the stop, largest recorded "
              "%.3f deg\n",
              last * deg, stopped_at, largest * deg);
  EXPECT_LE(largest * deg, 20.0); // every step before the stop within the limit
  EXPECT_GT(stopped_at, 20.0);
  EXPECT_LT(stopped_at - last * deg, 1.0); // one step of tipping (1 ms) later
  EXPECT_NEAR(sim.summary().max_waist_tilt * deg, stopped_at, 1e-3);
}

TEST(StabilizerLoop, StepAllocatesNothing) {
  // The push scene with noisy, delayed sensors: sensors, estimator (the ankle springs from the
  // F/T wrenches), stabilizer and push.
  HumanoidSimulation sim(testing::load_humanoid_scene(
      "push_stand", {{"Simulation/Duration", "1.5"},
                     {"Control/Passive joint estimate", "wrench"},
                     {"Control/Force noise", "2"},
                     {"Control/IMU orientation noise", "0.001"},
                     {"Control/Sensor delay", "2"},
                     // the noisy references make some contact solves stall near 3e-7 m/s
                     {"Contact/Failure residual", "1e-3"}}));
  for (int n = 0; n < 10; ++n)
    sim.step();
  const auto count = plantar::testing::count_allocations([&] {
    while (sim.steps_done() < sim.n_steps())
      sim.step();
  });
  const long n = count.during;
  std::printf("stabilized push scene: %ld allocations in %d steps\n", n, sim.n_steps() - 10);
  EXPECT_TRUE(count.counter_works);
  EXPECT_EQ(n, 0);
}

TEST(StabilizerLoop, PushedStepAdjustingWalkAllocatesNothing) {
  // The pushed walk with step adjustment and step timing over the push, the shortened swing
  // and the moved landing (3.2-4.1 s).
  auto overrides = pushed_walk(40, true, "1, 0, 0", true);
  overrides.push_back({"Simulation/Duration", "4.1"});
  HumanoidSimulation sim(testing::load_humanoid_scene("default", overrides));
  while (sim.steps_done() < 3200)
    sim.step();
  const auto count = plantar::testing::count_allocations([&] {
    while (sim.steps_done() < sim.n_steps())
      sim.step();
  });
  std::printf("pushed walk with step adjustment and timing: %ld allocations in %d steps, %d "
              "landings moved, %d swings shortened\n",
              count.during, sim.n_steps() - 3200, sim.summary().adjusted_steps,
              sim.summary().shortened_swings);
  EXPECT_TRUE(count.counter_works);
  EXPECT_EQ(count.during, 0);
  EXPECT_GE(sim.summary().adjusted_steps, 1);
  EXPECT_GE(sim.summary().shortened_swings, 1);
}

TEST(StabilizerScene, BadEntriesAreNamed) {
  auto message = [](const std::vector<std::pair<std::string, std::string>>& overrides) {
    try {
      HumanoidSimulation sim(testing::load_humanoid_scene("push_stand", overrides));
    } catch (const std::invalid_argument& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  const std::string frame = message({{"Control/IMU frame", "NO_SUCH_LINK"}});
  std::printf("%s\n", frame.c_str());
  EXPECT_NE(frame.find("Control/IMU frame = 'NO_SUCH_LINK'"), std::string::npos) << frame;
  const std::string sensor = message({{"Control/Right force sensor frame", "BODY"}});
  std::printf("%s\n", sensor.c_str());
  EXPECT_NE(sensor.find("force sensor frame 'BODY' is not on the foot's body"), std::string::npos)
      << sensor;
  const std::string duration = message({{"Simulation/Push duration", "0"}});
  std::printf("%s\n", duration.c_str());
  EXPECT_NE(duration.find("Simulation/Push duration = 0"), std::string::npos) << duration;
  const std::string gain = message({{"Control/Step adjustment gain", "3"}});
  std::printf("%s\n", gain.c_str());
  EXPECT_NE(gain.find("Control/Step adjustment gain = 3"), std::string::npos) << gain;
  const std::string speed = message({{"Control/Max step adjustment speed", "0"}});
  std::printf("%s\n", speed.c_str());
  EXPECT_NE(speed.find("Control/Max step adjustment speed = 0"), std::string::npos) << speed;
  const std::string timing = message({{"Control/Step timing time constant", "0"}});
  std::printf("%s\n", timing.c_str());
  EXPECT_NE(timing.find("Control/Step timing time constant = 0"), std::string::npos) << timing;
  const std::string damping = message({{"Control/Foot damping", "0"}});
  std::printf("%s\n", damping.c_str());
  EXPECT_NE(damping.find("Control/Foot damping = 0"), std::string::npos) << damping;
  const std::string tilt = message({{"Simulation/Fall tilt", "0"}});
  std::printf("%s\n", tilt.c_str());
  EXPECT_NE(tilt.find("Simulation/Fall tilt = 0"), std::string::npos) << tilt;
}

// Control/Foot damping rate: each axis's foot damping from what lies under the ankle, D = k / r
// with 1/k = 1/kp + 1/k_foot. The whole sole face's tilt stiffness against the confined layer's
// closed form E (1 - nu) / ((1 + nu)(1 - 2 nu)) I / t (I = L W^3 / 12 for roll, W L^3 / 12 for
// pitch; an upper bound of the converged sole that the free sides' bulging lowers by 4-8 %, the
// 3 cm P1 mesh's locking raises by about as much); then the published soft sole (0.23 x 0.13 x
// 0.021 m, E = 320 kPa, nu = 0.3, mu = 0.65; issue 23) on the default walk: with the default
// D = 2000 N m s/rad, tuned on the stiff walk, a node is squeezed through half the thickness at
// 3.40 s (the CoP loop's rate k / D is 0.4 /s in roll); at r = 12 /s it completes.
TEST(FootDampingRate, TheSoftSoleWalksWithTheDampingOfItsTiltStiffness) {
  const double E = 4e6, nu = 0.3, length = 0.2172, width = 0.138, thickness = 0.02;
  const double confined = E * (1 - nu) / ((1 + nu) * (1 - 2 * nu)) / thickness;
  HumanoidSimulation sole(
      testing::load_humanoid_scene("default", {{"Robot/Foot form", "fem sole"},
                                               {"Control/Foot damping rate", "12"},
                                               {"Simulation/Duration", "0.002"}}));
  const Eigen::Vector2d k = sole.summary().foot_tilt_stiffness;
  const Eigen::Vector2d closed(confined * length * std::pow(width, 3) / 12,
                               confined * width * std::pow(length, 3) / 12);
  std::printf("default sole, 3 cm P1: tilt stiffness roll %.0f, pitch %.0f N m/rad; confined "
              "layer %.0f, %.0f\n",
              k[0], k[1], closed[0], closed[1]);
  EXPECT_NEAR(k[0] / closed[0], 1, 0.1);
  EXPECT_NEAR(k[1] / closed[1], 1, 0.1);
  // summary.txt names the damping used and where it came from: D = k_eff / r, 1/k_eff = 1/kp +
  // 1/k (kp = Control/Joint stiffness, 1e5 N m/rad)
  const std::string text = format_summary(
      testing::load_humanoid_scene("default", {{"Robot/Foot form", "fem sole"}}), sole.summary());
  const auto at = text.find("foot admittance: damping roll ");
  ASSERT_NE(at, std::string::npos) << text;
  const double printed = std::strtod(text.c_str() + at + 30, nullptr);
  EXPECT_NEAR(printed, 1 / (1 / 1e5 + 1 / k[0]) / 12, 1e-5 * printed) << text.substr(at, 200);
  EXPECT_NE(text.find("Control/Foot damping rate 12 /s", at), std::string::npos);
  EXPECT_NE(text.find("F/T low-pass 25 Hz", at), std::string::npos);
  HumanoidSimulation ankle(
      testing::load_humanoid_scene("default", {{"Robot/Foot form", "compliant ankle"},
                                               {"Control/Foot damping rate", "12"},
                                               {"Simulation/Duration", "0.002"}}));
  EXPECT_EQ(ankle.summary().foot_tilt_stiffness, Eigen::Vector2d(600, 600)); // the springs

  const std::vector<std::pair<std::string, std::string>> soft{
      {"Robot/Foot form", "fem sole"},
      {"Sole/Length", "0.23"},
      {"Sole/Width", "0.13"},
      {"Sole/Thickness", "0.021"},
      {"Sole/Materials", "rubber: law=linear, E=3.2e5, nu=0.3"},
      {"Contact/Friction coefficient", "0.65"},
      {"Control/Foot damping rate", "0"},
      {"Control/Force sensor bandwidth", "0"},
      {"Simulation/Time step", "0.001"},
      {"Simulation/Theta", "1"}};
  HumanoidSimulation tuned(testing::load_humanoid_scene("default", soft));
  const std::string failure = testing::run_to_stop(tuned);
  std::printf("soft sole, Foot damping = %.0f: %s\n", tuned.summary().foot_damping[0],
              failure.c_str());
  EXPECT_NE(failure.find("compression"), std::string::npos) << failure;

  auto rated = soft;
  rated.emplace_back("Control/Foot damping rate", "12"); // set after the 0 above: it wins
  HumanoidSimulation matched(testing::load_humanoid_scene("default", rated));
  ASSERT_NO_THROW(matched.run());
  const HumanoidSummary& s = matched.summary();
  const double kp = 1e5; // Control/Joint stiffness of the scene
  for (int axis = 0; axis < 2; ++axis)
    EXPECT_NEAR(s.foot_damping[axis], 1 / (1 / kp + 1 / s.foot_tilt_stiffness[axis]) / 12,
                1e-12 * s.foot_damping[axis]);
  const double right = (s.final_right_sole - s.planned_right_sole).head<2>().norm();
  const double left = (s.final_left_sole - s.planned_left_sole).head<2>().norm();
  std::printf("soft sole, Foot damping rate = 12 /s: tilt stiffness %.0f, %.0f N m/rad, D = "
              "%.1f, %.1f N m s/rad; completes, waist within %.2f deg, soles %.1f, %.1f mm from "
              "plan\n",
              s.foot_tilt_stiffness[0], s.foot_tilt_stiffness[1], s.foot_damping[0],
              s.foot_damping[1], s.max_waist_tilt * 180 / M_PI, right * 1e3, left * 1e3);
  EXPECT_LT(s.foot_tilt_stiffness[0], 2 * s.robot_mass * 9.81 * 0.815); // a soft support
  EXPECT_LT(s.max_waist_tilt * 180 / M_PI, 5.0);
  EXPECT_LT(right, 0.02);
  EXPECT_LT(left, 0.02);
}

TEST(PushedWalk, StepAdjustmentRecoversWhatTheAnkleCannot) {
  // Forward 40 N s and sideways (to the right, the swing foot's side) 30 N s: the ankle strategy
  // alone recovers 35 and 25 N s (docs/stabilizer.md).
  struct Case {
    double impulse;
    const char* direction;
    Eigen::Vector2d along;
  };
  for (const Case& c : {Case{40, "1, 0, 0", {1, 0}}, Case{30, "0, -1, 0", {0, -1}}}) {
    HumanoidSimulation ankle(
        testing::load_humanoid_scene("default", pushed_walk(c.impulse, false, c.direction)));
    const std::string failure = testing::run_to_stop(ankle);
    std::printf("%.0f N s along (%s), ankle strategy only: %s\n", c.impulse, c.direction,
                failure.c_str());
    EXPECT_NE(failure.find("the robot fell"), std::string::npos) << failure;

    HumanoidSimulation stepping(
        testing::load_humanoid_scene("default", pushed_walk(c.impulse, true, c.direction)));
    ASSERT_NO_THROW(stepping.run());
    const HumanoidSummary& s = stepping.summary();
    const walking::BalanceController& balance = *stepping.balance();
    const Eigen::Vector2d shift = s.step_plan_shift;
    // Where the feet ended against where the loop takes them to be (their sensed landings; the
    // difference is the feet's slip after landing, which nothing senses).
    const double right =
        (s.final_right_sole.head<2>() - s.planned_right_sole.head<2>() - s.final_anchor_shifts[0])
            .norm();
    const double left =
        (s.final_left_sole.head<2>() - s.planned_left_sole.head<2>() - s.final_anchor_shifts[1])
            .norm();
    // The robot ends over its feet: the true DCM against the feet's midpoint, inside the
    // double support's box (x: the sole's half length; y: half the feet's distance plus the
    // sole's half width).
    const Eigen::Vector2d dcm = balance.reference_dcm() + balance.statistics().true_dcm_error;
    const Eigen::Vector2d feet = (s.final_left_sole - s.final_right_sole).head<2>();
    const Eigen::Vector2d off = dcm - 0.5 * (s.final_right_sole + s.final_left_sole).head<2>();
    std::printf("with step adjustment: completes; %d landings moved, the largest by %.1f mm, the "
                "landings up to %.1f mm from their targets, plan shifted by (%.1f, %.1f) mm; "
                "soles %.2f, %.2f mm from their anchors; final true DCM (%.1f, %.1f) mm from the "
                "feet's midpoint, max tilt %.2f deg\n",
                s.adjusted_steps, s.max_step_adjustment * 1e3, s.max_landing_error * 1e3,
                shift.x() * 1e3, shift.y() * 1e3, right * 1e3, left * 1e3, off.x() * 1e3,
                off.y() * 1e3, s.max_waist_tilt * 180 / M_PI);
    EXPECT_GE(s.adjusted_steps, 1);
    EXPECT_GT(s.max_step_adjustment, 0.02);
    // Under half the sole's length (measured: 72-99 mm; the moved foot rocks heel to toe and
    // edge to edge after its landing, docs/stabilizer.md).
    EXPECT_LT(right, 0.11);
    EXPECT_LT(left, 0.11);
    EXPECT_LT(std::abs(off.x()), 0.1);
    EXPECT_LT(std::abs(off.y()), 0.5 * std::abs(feet.y()) + 0.06);
  }

  // Unpushed, no landing moves and the walk is the same bit for bit.
  HumanoidSimulation off(testing::load_humanoid_scene("default", pushed_walk(0, false)));
  HumanoidSimulation on(testing::load_humanoid_scene("default", pushed_walk(0, true)));
  ASSERT_NO_THROW(off.run());
  ASSERT_NO_THROW(on.run());
  EXPECT_EQ(on.summary().adjusted_steps, 0);
  EXPECT_EQ(on.summary().max_step_adjustment, 0.0);
  EXPECT_EQ(differing_entries(off.waist_series(), on.waist_series()), 0);
}

TEST(PushedWalk, StepTimingAddsToStepAdjustment) {
  // Sideways (to the right, the swing foot's side) 40 N s: step adjustment alone falls (at all
  // four dt x theta settings of bench/robustness/push_walk_timing_sideways.prm); with step timing
  // too the swing lands earlier as well as further, and the walk completes (at all four; to
  // 55 N s, docs/stabilizer.md).
  HumanoidSimulation placed(
      testing::load_humanoid_scene("default", pushed_walk(40, true, "0, -1, 0")));
  const std::string failure = testing::run_to_stop(placed);
  std::printf("40 N s sideways, step adjustment only: %s\n", failure.c_str());
  EXPECT_NE(failure.find("the robot fell"), std::string::npos) << failure;

  HumanoidSimulation timed(
      testing::load_humanoid_scene("default", pushed_walk(40, true, "0, -1, 0", true)));
  ASSERT_NO_THROW(timed.run());
  const HumanoidSummary& s = timed.summary();
  const walking::BalanceController& balance = *timed.balance();
  const Eigen::Vector2d dcm = balance.reference_dcm() + balance.statistics().true_dcm_error;
  const Eigen::Vector2d feet = (s.final_left_sole - s.final_right_sole).head<2>();
  const Eigen::Vector2d off = dcm - 0.5 * (s.final_right_sole + s.final_left_sole).head<2>();
  std::printf("with step timing too: completes; %d swings shortened, the reference up to %.2f "
              "times the plan's rate, %.0f ms ahead at the end; %d landings moved, the largest "
              "by %.1f mm; final true DCM (%.1f, %.1f) mm from the feet's midpoint\n",
              s.shortened_swings, s.max_timing_rate, s.timing_advance * 1e3, s.adjusted_steps,
              s.max_step_adjustment * 1e3, off.x() * 1e3, off.y() * 1e3);
  EXPECT_GE(s.shortened_swings, 1);
  EXPECT_GT(s.max_timing_rate, 1.1);
  // The plan's remaining steps were played earlier by at least 10 ms of the 0.38 s left of the
  // pushed swing after its freeze time (measured: 92 ms).
  EXPECT_GT(s.timing_advance, 0.01);
  EXPECT_GE(s.adjusted_steps, 1);
  EXPECT_LT(std::abs(off.x()), 0.1);
  EXPECT_LT(std::abs(off.y()), 0.5 * std::abs(feet.y()) + 0.06);

  // Unpushed, the ankle takes every error: the reference keeps the plan's time, bit for bit.
  HumanoidSimulation off_run(testing::load_humanoid_scene("default", pushed_walk(0, false)));
  HumanoidSimulation on_run(
      testing::load_humanoid_scene("default", pushed_walk(0, false, "1, 0, 0", true)));
  ASSERT_NO_THROW(off_run.run());
  ASSERT_NO_THROW(on_run.run());
  EXPECT_EQ(on_run.summary().shortened_swings, 0);
  EXPECT_EQ(on_run.summary().timing_advance, 0.0);
  EXPECT_EQ(differing_entries(off_run.waist_series(), on_run.waist_series()), 0);
}

class StabilizedWalk : public ::testing::TestWithParam<const char*> {};

TEST_P(StabilizedWalk, SixStepsCompleteAndTheEstimateFollowsTheTruth) {
  HumanoidSimulation sim(testing::load_humanoid_scene(
      "walk", {{"Robot/Foot form", GetParam()}, {"Control/Stabilizer", "dcm"}}));
  ASSERT_NO_THROW(sim.run());
  const walking::BalanceStatistics& s = sim.balance()->statistics();
  const HumanoidSummary& summary = sim.summary();
  const double right = (summary.final_right_sole - summary.planned_right_sole).norm();
  const double left = (summary.final_left_sole - summary.planned_left_sole).norm();
  std::printf("%s walk with the stabilizer: completed, peak waist |a_z| %.3f m/s^2, max DCM "
              "error %.4f m; estimate vs truth: CoM %.4f m, DCM %.4f m; soles %.4f %.4f m "
              "from plan\n",
              GetParam(), summary.max_waist_acceleration_z, s.max_dcm_error,
              s.max_com_estimate_error, s.max_dcm_estimate_error, right, left);
  EXPECT_LT(right, 0.01);
  EXPECT_LT(left, 0.01);
  // The estimate (encoders, IMU, contact anchoring) against the ground truth, bounds of
  // docs/stabilizer.md (measured 1.1 / 7.1 / 1.0 mm for the CoM, 4.7 / 32 / 4.0 mm for the
  // DCM): the compliant ankle's spring deflection is not sensed, hence its larger bound.
  const bool springs = std::string(GetParam()) == "compliant ankle";
  EXPECT_LT(s.max_com_estimate_error, springs ? 0.01 : 0.002);
  EXPECT_LT(s.max_dcm_estimate_error, springs ? 0.04 : 0.008);
}

INSTANTIATE_TEST_SUITE_P(FootForms, StabilizedWalk, ::testing::ValuesIn(testing::foot_forms),
                         [](const auto& info) { return testing::foot_form_name(info); });

} // namespace
} // namespace plantar::app
