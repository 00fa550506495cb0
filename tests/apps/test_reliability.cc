// Issue 27's examples and the validity guards (docs/reliability.md):
// - HRP-2 dropped from 30 cm onto linear soles of E = 10 kPa stops when a node is compressed
//   past Sole/Max compression (0.5 x thickness), the message naming Sole/Model = hyperelastic;
//   the step it stops at is the first whose compression, recomputed here from the soles' node
//   displacements, is past the limit;
// - the rigid walk's unconverged solves: with the old settings (gauss-seidel, failure residual
//   1e-2 m/s) every one is listed with its step, time, residual and contact count, as in
//   contacts.csv's row of that step; with the shipped settings (auto, 10 x Tolerance) none;
// - the drop with E = 1e12 Pa at dt = 10 ms and ADMM stops with a message whose first
//   suggestion, applied, runs to the end with every solve converged and the weight carried;
// - every shipped humanoid scene uses auto and the failure residual 10 x Tolerance (the walks
//   and leans 1000 x, docs/reliability.md);
// - the linear sole's guard against a closed form: the sole's vertical stiffness between the
//   bonds E A / t (uniaxial stress) and E_oed A / t (laterally confined), and the static
//   compression of a standing robot between F t / (E_oed A) and F t / (E A); the warning raised
//   at exactly the first step whose compression (recomputed here) crosses Sole/Compression
//   warning, counted on every step past it, and not raised by a level above the peak;
// - the hyperelastic sole's det F guard: the warning at the first step whose min J (read here
//   from both soles) is below the level, and past the failure level the run stops there with
//   the remedies (smaller dt, finer mesh, mixed formulation).
#include "apps/condensed_sole_foot.h"
#include "apps/humanoid_simulation.h"
#include "apps/hyperelastic_sole_foot.h"
#include "contact/contact_solver.h"
#include "contact/ground_frame.h"
#include "coupling/condensed_sole.h"
#include "coupling/nonlinear_condensed_sole.h"
#include "humanoid_test_utilities.h"
#include "multibody/kinematics.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <regex>
#include <sstream>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include <unistd.h>

namespace plantar::app {
namespace {

using testing::load_humanoid_scene;
using Overrides = std::vector<std::pair<std::string, std::string>>;

constexpr double g = 9.81;

/// max over both soles and their nodes of u . n / t (n: the sole's normal into the foot,
/// world), computed here from the node displacements and the kinematics.
double max_compression(const HumanoidSimulation& sim, double thickness) {
  const auto& feet = dynamic_cast<const SolePatchFoot&>(sim.foot_model());
  multibody::Data data(sim.model());
  multibody::forward_kinematics(sim.model(), data, sim.q());
  double result = 0;
  for (int foot = 0; foot < 2; ++foot) {
    const int frame = feet.sole_frame(foot);
    const multibody::SE3 sole = multibody::frame_placement(sim.model(), data, frame);
    const Eigen::Vector3d normal = sole.rotation.col(2);
    const Eigen::VectorXd& u = feet.pad(foot).displacement();
    for (int k = 0; k < feet.pad(foot).n_nodes(); ++k)
      result = std::max(result, contact::ground_to_world(u.segment<3>(3 * k)).dot(normal));
  }
  return result / thickness;
}

TEST(Reliability, SoftLinearSoleDropFromThirtyCentimetresFails) {
  const Scene scene =
      load_humanoid_scene("drop", {{"Robot/Foot form", "fem sole"},
                                   {"Sole/Materials", "rubber: law=linear, E=1e4, nu=0.3"},
                                   {"Simulation/Release height", "0.3"}});
  HumanoidSimulation sim(scene);
  const double t = scene.sole.thickness, limit = scene.sole_validity.max_compression;
  double previous = 0;
  std::string what;
  try {
    while (sim.steps_done() < sim.n_steps()) {
      previous = max_compression(sim, t);
      sim.step();
    }
  } catch (const std::runtime_error& e) {
    what = e.what();
  }
  std::printf("30 cm onto E = 10 kPa: %s\n", what.c_str());
  ASSERT_FALSE(what.empty()) << "the run did not stop";
  std::smatch match;
  ASSERT_TRUE(std::regex_search(
      what, match,
      std::regex("step ([0-9]+), t = ([0-9.e-]+) s: linear sole compression / thickness = "
                 "([0-9.e-]+) \\((right|left) sole\\) > Sole/Max compression = 0.5: .*"
                 "Sole/Model = hyperelastic")))
      << what;
  const double value = std::stod(match[3]), now = max_compression(sim, t);
  std::printf("compression / thickness: %.6g before the failing step, %.6g at it (recomputed "
              "%.6g); limit %.2f; first contact at sqrt(2 h / g) = %.4f s\n",
              previous, value, now, limit, std::sqrt(2 * 0.3 / g));
  EXPECT_EQ(std::stoi(match[1]), sim.steps_done());
  EXPECT_NEAR(value, now, 1e-5 * now); // the message prints 6 digits
  EXPECT_GT(now, limit);
  EXPECT_LE(previous, limit);
  EXPECT_GT(std::stod(match[2]), std::sqrt(2 * 0.3 / g)); // after the landing
}

/// Rows of a CSV file (header skipped).
std::vector<std::vector<std::string>> read_rows(const std::filesystem::path& path) {
  std::ifstream in(path);
  std::vector<std::vector<std::string>> rows;
  std::string line;
  std::getline(in, line);
  while (std::getline(in, line)) {
    std::vector<std::string> fields;
    std::stringstream s(line);
    for (std::string field; std::getline(s, field, ',');)
      fields.push_back(field);
    rows.push_back(fields);
  }
  return rows;
}

TEST(Reliability, WalkUnconvergedSolvesAreListed) {
  const std::filesystem::path dir = std::filesystem::temp_directory_path() /
                                    ("plantar_reliability_walk_" + std::to_string(::getpid()));
  {
    // The settings of issue 27's example: Gauss-Seidel, failure residual 1e-2 m/s.
    const Scene scene = load_humanoid_scene(
        "walk", {{"Contact/Solver", "gauss-seidel"}, {"Contact/Failure residual", "1e-2"}});
    HumanoidSimulation sim(scene);
    sim.run();
    sim.write_csv(dir);
    const HumanoidSummary& s = sim.summary();
    const auto listed = read_rows(dir / "unconverged_solves.csv");
    const TimeSeries& contacts = sim.contact_series();
    std::printf("rigid walk, gauss-seidel: %d of %d solves unconverged, max residual %.3g m/s; "
                "%zu listed\n",
                s.n_unconverged, s.n_solves, s.max_solver_residual, listed.size());
    EXPECT_GT(s.n_unconverged, 0);
    ASSERT_EQ(static_cast<int>(listed.size()), s.n_unconverged);
    ASSERT_EQ(static_cast<int>(sim.unconverged_solves().list().size()), s.n_unconverged);
    for (const auto& row : listed) {
      ASSERT_EQ(row.size(), 9u);
      const int step = std::stoi(row[0]);
      const double residual = std::stod(row[2]);
      // Output every = 1: the row of step n is n - 1.
      EXPECT_DOUBLE_EQ(std::stod(row[1]), contacts(step - 1, contacts.column("t")));
      EXPECT_DOUBLE_EQ(residual, contacts(step - 1, contacts.column("solver_residual")));
      EXPECT_EQ(std::stoi(row[3]), contacts(step - 1, contacts.column("n_contacts")));
      EXPECT_EQ(std::stoi(row[4]), contacts(step - 1, contacts.column("solver_iterations")));
      EXPECT_GT(residual, scene.contact.tolerance);
      EXPECT_LE(residual, scene.contact.failure_residual);
      EXPECT_EQ(row[6], "gauss-seidel");
    }
    // Every row of contacts.csv above the tolerance is listed.
    int above = 0;
    for (int r = 0; r < contacts.n_rows(); ++r)
      above += contacts(r, contacts.column("solver_residual")) > scene.contact.tolerance ? 1 : 0;
    EXPECT_EQ(above, s.n_unconverged);
  }
  {
    // The shipped settings: auto, failure residual 10 x Tolerance.
    const Scene scene = load_humanoid_scene("walk", {});
    HumanoidSimulation sim(scene);
    sim.run();
    const HumanoidSummary& s = sim.summary();
    std::printf("rigid walk, auto: %d of %d solves unconverged, max residual %.3g m/s "
                "(tolerance %.1e); switches to Newton: slow %d, stalled %d, budget %d\n",
                s.n_unconverged, s.n_solves, s.max_solver_residual, scene.contact.tolerance,
                s.n_switch_slow, s.n_switch_stalled, s.n_switch_budget);
    EXPECT_EQ(s.n_unconverged, 0);
    EXPECT_LE(s.max_solver_residual, scene.contact.tolerance);
  }
  std::filesystem::remove_all(dir);
}

/// The numbers of a written problem or start (one per line).
std::vector<double> numbers_of(const std::string& text) {
  std::istringstream in(text);
  std::vector<double> numbers;
  for (double x; in >> x;)
    numbers.push_back(x);
  return numbers;
}

TEST(Reliability, StiffSoleLargeStepSuggestsASettingThatWorks) {
  // The iterative solvers alone: the direct solve (with its sliding contacts) takes this
  // drop's steps itself, so ADMM's failure is shown with it off.
  const Overrides stiff = {{"Robot/Foot form", "fem sole"},
                           {"Sole/Materials", "rubber: law=linear, E=1e12, nu=0.3"},
                           {"Simulation/Time step", "0.01"},
                           {"Contact/Max iterations", "500"},
                           {"Contact/Sticking direct solve", "false"}};
  Overrides admm = stiff;
  admm.push_back({"Contact/Solver", "admm"});
  std::string what;
  {
    HumanoidSimulation sim(load_humanoid_scene("drop", admm));
    what = testing::run_to_stop(sim);
    // The failed solve's problem, as written for replay (contact/siconos_writer.h): 3, n, the
    // dense W's header, its 9 n^2 entries, q = v_free + b e_n and mu, exactly the stepper's.
    const std::vector<double> numbers = numbers_of(sim.failed_contact_problem());
    const contact::ContactProblem& problem = sim.stepper().problem();
    const int n = problem.n_contacts;
    ASSERT_GT(n, 0);
    ASSERT_EQ(numbers.size(), static_cast<std::size_t>(7 + 9 * n * n + 4 * n));
    EXPECT_EQ(numbers[1], n);
    EXPECT_NE(what.find(", " + std::to_string(n) + " contacts"), std::string::npos) << what;
    Eigen::MatrixXd w;
    problem.assemble_delassus(w);
    double worst = 0;
    for (int j = 0; j < 3 * n; ++j)
      for (int i = 0; i < 3 * n; ++i)
        worst = std::max(worst, std::abs(numbers[7 + 3 * n * j + i] - w(i, j)));
    for (int k = 0; k < n; ++k) {
      const double q_n = numbers[7 + 9 * n * n + 3 * k];
      worst =
          std::max(worst, std::abs(q_n - (problem.free_velocity[3 * k] + problem.normal_bias[k])));
      worst = std::max(worst, std::abs(numbers[7 + 9 * n * n + 3 * n + k] - problem.friction[k]));
    }
    std::printf("failed solve written: %d contacts, largest difference %.1e\n", n, worst);
    EXPECT_EQ(worst, 0.0);
    // Its start (failed/warm_start.txt) is the stepper's warm start (FailedSolveReplays...).
    EXPECT_EQ(sim.failed_warm_start().empty(), false);
  }
  std::printf("E = 1e12 Pa, dt = 10 ms, admm: %s\n", what.c_str());
  ASSERT_FALSE(what.empty()) << "the ADMM run did not stop";
  std::smatch match;
  ASSERT_TRUE(
      std::regex_search(what, match, std::regex("try: ([A-Za-z ]+)/([A-Za-z ]+) = ([^ ;]+)")))
      << what;
  const std::string setting = std::string(match[1]) + "/" + std::string(match[2]);
  EXPECT_EQ(setting + " = " + std::string(match[3]), "Contact/Solver = auto");
  Overrides suggested = admm;
  suggested.push_back({setting, match[3]});
  const Scene scene = load_humanoid_scene("drop", suggested);
  HumanoidSimulation sim(scene);
  sim.run();
  const HumanoidSummary& s = sim.summary();
  const double weight = sim.model().total_mass() * g;
  std::printf("with %s = %s: %d steps, %d of %d solves unconverged, max residual %.3g m/s, "
              "final force %.2f N vs m g %.2f N\n",
              setting.c_str(), std::string(match[3]).c_str(), s.n_steps, s.n_unconverged,
              s.n_solves, s.max_solver_residual, s.final_contact_force.z(), weight);
  EXPECT_EQ(s.n_steps, sim.n_steps());
  EXPECT_EQ(s.n_unconverged, 0);
  EXPECT_NEAR(s.final_contact_force.z() / weight, 1.0, 0.01);
}

// A run stopped by a contact solve writes that solve's start next to its problem
// (failed/warm_start.txt): 3, n, then the stepper's warm start bit for bit. The solve replayed
// from it by a new solver with the run's settings ends as the run's did (iterations, residual):
// the written problem and start are the whole solve. (auto, here with a budget of 10
// iterations, keeps nothing between solves; ADMM keeps its last rho, so its replay differs.)
TEST(Reliability, FailedSolveReplaysFromItsWrittenStart) {
  const Overrides small_budget = {{"Contact/Max iterations", "10"}};
  HumanoidSimulation sim(load_humanoid_scene("walk", small_budget));
  const std::string what = testing::run_to_stop(sim);
  ASSERT_FALSE(what.empty()) << "the run did not stop";
  const contact::ContactProblem& problem = sim.stepper().problem();
  const int n = problem.n_contacts;
  const std::vector<double> written = numbers_of(sim.failed_warm_start());
  ASSERT_EQ(written.size(), static_cast<std::size_t>(2 + 3 * n));
  EXPECT_EQ(written[0], 3);
  EXPECT_EQ(written[1], n);
  const Eigen::Map<const Eigen::VectorXd> start(written.data() + 2, 3 * n);
  EXPECT_EQ((start.array() != sim.stepper().warm_start().array()).count(), 0);
  EXPECT_GT(start.norm(), 0.0); // the solve did not start from zero
  contact::ContactSolver replay(n, problem.rigid_rank());
  Eigen::VectorXd r = start;
  const contact::SolverResult again = replay.solve(problem, sim.stepper().parameters().solver, r);
  std::smatch run;
  ASSERT_TRUE(std::regex_search(
      what, run, std::regex("after ([0-9]+) iterations \\([^)]*\\), residual ([^ ]+) m/s")))
      << what;
  std::printf("replayed from the written start: %d iterations, residual %.6g m/s (the run: %s, "
              "%s m/s)\n",
              again.iterations, again.residual, std::string(run[1]).c_str(),
              std::string(run[2]).c_str());
  EXPECT_EQ(again.iterations, std::stoi(run[1]));
  EXPECT_NEAR(again.residual / std::stod(run[2]), 1.0, 1e-5);
  // From zero, as replays were before: another solve.
  Eigen::VectorXd zero = Eigen::VectorXd::Zero(3 * n);
  const contact::SolverResult cold = replay.solve(problem, sim.stepper().parameters().solver, zero);
  std::printf("%s\nfrom zero: %d iterations, residual %.6g m/s\n", what.substr(0, 120).c_str(),
              cold.iterations, cold.residual);
  EXPECT_GT(std::abs(cold.residual / again.residual - 1.0), 0.01);
}

TEST(Reliability, ShippedScenesUseAutoAndTheStrictFailureResidual) {
  int n_scenes = 0;
  const std::filesystem::path scenes = std::filesystem::path(PLANTAR_SOURCE_DIR) / "scenes";
  for (const auto& entry : std::filesystem::recursive_directory_iterator(scenes)) {
    if (entry.path().extension() != ".prm")
      continue;
    dealii::ParameterHandler prm;
    const Scene scene = load_scene(entry.path(), prm);
    if (scene.type == SceneType::static_sole || scene.robot.urdf_file.empty())
      continue;
    ++n_scenes;
    const double factor = ContactParameters::default_failure_factor;
    EXPECT_EQ(scene.contact.solver, contact::ContactSolverType::automatic) << entry.path();
    EXPECT_DOUBLE_EQ(scene.contact.failure_residual, factor * scene.contact.tolerance)
        << entry.path();
  }
  std::printf("%d humanoid scenes checked\n", n_scenes);
  EXPECT_GE(n_scenes, 13);
}

TEST(Reliability, LinearSoleGuardAgainstClosedForm) {
  const double E = 2e5, nu = 0.3, warning = 0.03;
  const Scene scene =
      load_humanoid_scene("stand", {{"Robot/Foot form", "fem sole"},
                                    {"Sole/Materials", "rubber: law=linear, E=2e5, nu=0.3"},
                                    {"Sole/Compression warning", "0.03"},
                                    {"Sole/Strain warning", "10"},
                                    {"Sole/Max strain", "20"},
                                    {"Simulation/Duration", "0.6"},
                                    {"Simulation/Settle time", "0.3"}});
  HumanoidSimulation sim(scene);
  const double t = scene.sole.thickness, area = scene.sole.length * scene.sole.width;
  const double e_oed = E * (1 - nu) / ((1 + nu) * (1 - 2 * nu));
  // Stiffness bounds of a layer pressed uniformly (top fixed, bottom free to slide).
  const double k = sim.summary().foot_stiffness;
  std::printf("sole stiffness %.5g N/m; bounds E A / t = %.5g, E_oed A / t = %.5g\n", k,
              E * area / t, e_oed * area / t);
  EXPECT_GE(k, E * area / t);
  EXPECT_LE(k, e_oed * area / t);

  int first_step = 0, n_past = 0;
  double peak = 0;
  while (sim.steps_done() < sim.n_steps()) {
    sim.step();
    const double c = max_compression(sim, t);
    peak = std::max(peak, c);
    if (c > warning) {
      ++n_past;
      if (first_step == 0)
        first_step = sim.steps_done();
    }
  }
  const HumanoidSummary& s = sim.summary();
  ASSERT_GE(s.validity.size(), 1);
  const ValidityRecord& r = s.validity.record(0);
  ASSERT_STREQ(r.limit.key, "sole_compression");
  std::printf("compression / thickness: peak %.5g (guard %.5g), first past %.2f at step %d "
              "(guard %d), %d steps past it (guard %d)\n",
              peak, r.peak, warning, first_step, r.first_warning_step, n_past, r.n_warning_steps);
  EXPECT_NEAR(r.peak, peak, 1e-12);
  EXPECT_GT(first_step, 0);
  EXPECT_EQ(r.first_warning_step, first_step);
  EXPECT_EQ(r.n_warning_steps, n_past);
  ASSERT_EQ(s.validity.n_warnings(), 1); // compression only: the strain level is above its peak
  EXPECT_FALSE(s.validity.record(1).warned());

  // The static compression (area-weighted mean over each sole's nodes) against F t / (E A)
  // and F t / (E_oed A), F the foot's vertical force at the end.
  const auto& feet = dynamic_cast<const CondensedSoleFoot&>(sim.foot_model());
  const coupling::CondensedSole& sole = *feet.sole();
  Eigen::VectorXd unit_load(3 * sole.n_contacts());
  sole.contact_load(Eigen::Vector3d(0, 0, 1), unit_load);
  const TimeSeries& contacts = sim.contact_series();
  const int last = contacts.n_rows() - 1;
  for (int foot = 0; foot < 2; ++foot) {
    const Eigen::VectorXd& u = feet.pad(foot).displacement(); // (n, t1, t2): n = world z
    double weighted = 0, total = 0;
    for (int n = 0; n < sole.n_contacts(); ++n) {
      weighted += unit_load[3 * n + 2] * u[3 * n];
      total += unit_load[3 * n + 2];
    }
    const double mean = weighted / total;
    const double force = contacts(last, contacts.column(foot == 0 ? "right_fz" : "left_fz"));
    std::printf("foot %d: force %.2f N, mean compression %.5g mm; bounds %.5g .. %.5g mm\n", foot,
                force, mean * 1e3, force * t / (e_oed * area) * 1e3, force * t / (E * area) * 1e3);
    EXPECT_GE(mean, force * t / (e_oed * area));
    EXPECT_LE(mean, force * t / (E * area));
  }
}

/// min over both hyperelastic soles of det F at their last Newton solve.
double min_jacobian(const HumanoidSimulation& sim) {
  const auto& feet = dynamic_cast<const HyperelasticSoleFoot&>(sim.foot_model());
  return std::min(feet.sole(0).sole().elasticity().min_jacobian(),
                  feet.sole(1).sole().elasticity().min_jacobian());
}

TEST(Reliability, HyperelasticSoleJacobianGuard) {
  const double level = 0.999;
  const Overrides overrides = {{"Simulation/Duration", "0.1"}, {"Sole/Jacobian warning", "0.999"}};
  int first_step = 0, n_past = 0;
  double lowest = 1;
  {
    HumanoidSimulation sim(load_humanoid_scene("drop_nonlinear", overrides));
    while (sim.steps_done() < sim.n_steps()) {
      sim.step();
      const double j = min_jacobian(sim);
      lowest = std::min(lowest, j);
      if (j < level) {
        ++n_past;
        if (first_step == 0)
          first_step = sim.steps_done();
      }
    }
    const ValidityRecord& r = sim.summary().validity.record(0);
    ASSERT_STREQ(r.limit.key, "sole_min_jacobian");
    std::printf("hyperelastic drop: min det F %.6f (guard %.6f), first below %.3f at step %d "
                "(guard %d), %d steps below (guard %d)\n",
                lowest, r.peak, level, first_step, r.first_warning_step, n_past, r.n_warning_steps);
    EXPECT_GT(first_step, 0);
    EXPECT_DOUBLE_EQ(r.peak, lowest);
    EXPECT_EQ(r.first_warning_step, first_step);
    EXPECT_EQ(r.n_warning_steps, n_past);
  }
  Overrides failing = overrides;
  failing.push_back({"Sole/Min jacobian", "0.999"});
  HumanoidSimulation sim(load_humanoid_scene("drop_nonlinear", failing));
  const std::string what = testing::run_to_stop(sim);
  std::printf("Min jacobian 0.999: %s\n", what.c_str());
  EXPECT_NE(what.find("step " + std::to_string(first_step) + ","), std::string::npos) << what;
  EXPECT_NE(what.find("< Sole/Min jacobian = 0.999"), std::string::npos) << what;
  EXPECT_NE(what.find("Sole/Formulation = mixed"), std::string::npos) << what;
}

} // namespace
} // namespace plantar::app
