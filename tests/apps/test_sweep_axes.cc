// plantar sweep's general axes (Sweep/Axis N = Subsection/Entry = v1; v2): a 2 x 2 grid over
// Simulation/Theta and Contact/Friction coefficient of a short rigid-foot drop gives, per point,
// the figures of a `plantar run` of the scene with the two entries written by hand; sweep.csv
// carries one column per axis with the point's value. An undeclared entry, an entry with its
// own axis and a value out of its entry's range stop the sweep with a message naming the axis,
// before any output is written.
#include "tests/apps/cli_test_utilities.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>
#include <string>
#include <vector>

namespace {

namespace fs = std::filesystem;

using plantar::test::read_text;
using plantar::test::run_plantar;
using plantar::test::summary_value;

/// scenes/drop.prm on rigid feet, 0.1 s (the impact at 0.045 s), with @p tail appended.
fs::path scene_file(const std::string& name, const std::string& tail) {
  const fs::path path = fs::current_path() / name;
  std::ofstream(path) << read_text(std::string(PLANTAR_SOURCE_DIR) + "/scenes/drop.prm")
                      << "subsection Robot\n  set Foot form = rigid\nend\n"
                         "subsection Simulation\n  set Duration = 0.1\nend\n"
                      << tail;
  return path;
}

/// The rows of a CSV file split at commas (no quoted fields in this test's files).
std::vector<std::vector<std::string>> csv_rows(const fs::path& path) {
  std::ifstream in(path);
  std::vector<std::vector<std::string>> rows;
  std::string line;
  while (std::getline(in, line)) {
    rows.emplace_back();
    std::stringstream fields(line);
    std::string cell;
    while (std::getline(fields, cell, ','))
      rows.back().push_back(cell);
  }
  return rows;
}

TEST(SweepAxes, GridPointsEqualTheSingleRuns) {
  const fs::path sweep =
      scene_file("axes-sweep.prm", "subsection Sweep\n"
                                   "  set Axis 1 = Simulation/Theta = 0.5; 1\n"
                                   "  set Axis 2 = Contact/Friction coefficient = 0.3; 0.9\n"
                                   "end\n");
  const fs::path out = fs::current_path() / "axes-sweep";
  fs::remove_all(out);
  const auto s = run_plantar("sweep " + sweep.string() + " -o " + out.string() + " -j 2");
  std::printf("%s", s.output.c_str());
  ASSERT_EQ(s.status, 0) << s.output;

  // sweep.csv: 4 rows, the axes' columns last, named by their entries.
  const auto rows = csv_rows(out / "sweep.csv");
  ASSERT_EQ(rows.size(), 5u);
  const auto& header = rows[0];
  ASSERT_GE(header.size(), 2u);
  EXPECT_EQ(header[header.size() - 2], "Simulation/Theta");
  EXPECT_EQ(header.back(), "Contact/Friction coefficient");
  std::map<std::string, std::pair<std::string, std::string>> values; // id -> (theta, mu)
  for (std::size_t r = 1; r < rows.size(); ++r) {
    ASSERT_EQ(rows[r].size(), header.size()) << r;
    values[rows[r][0]] = {rows[r][header.size() - 2], rows[r].back()};
  }

  const struct {
    const char *theta, *mu, *id;
  } points[] = {{"0.5", "0.3", "rigid_dt1ms_theta0.5_frictioncoefficient0.3"},
                {"1", "0.9", "rigid_dt1ms_theta1_frictioncoefficient0.9"}};
  double previous = NAN;
  for (const auto& p : points) {
    ASSERT_EQ(values.count(p.id), 1u) << p.id << "\n" << read_text(out / "sweep.csv");
    EXPECT_EQ(values[p.id].first, p.theta);
    EXPECT_EQ(values[p.id].second, p.mu);
    const fs::path single =
        scene_file(std::string("axes-single-") + p.id + ".prm",
                   std::string("subsection Simulation\n  set Theta = ") + p.theta +
                       "\nend\nsubsection Contact\n  set Friction "
                       "coefficient = " +
                       p.mu + "\nend\n");
    const fs::path single_out = fs::current_path() / (std::string("axes-single-") + p.id);
    fs::remove_all(single_out);
    const auto r =
        run_plantar("run " + single.string() + " -o " + single_out.string() + " --no-figures");
    ASSERT_EQ(r.status, 0) << r.output;
    const fs::path point = out / "points" / p.id / "summary.csv";
    for (const char* name : {"max_waist_acceleration_z", "max_landing_peak_force", "n_steps"}) {
      const double a = summary_value(point, name),
                   b = summary_value(single_out / "summary.csv", name);
      std::printf("%s: %s sweep %.10e, single run %.10e\n", p.id, name, a, b);
      EXPECT_NEAR(a, b, 1e-12 * std::abs(b)) << p.id << " " << name;
    }
    const double peak = summary_value(point, "max_waist_acceleration_z");
    if (!std::isnan(previous)) { // theta reached the stepper: the two peaks differ
      EXPECT_GT(std::abs(peak - previous), 1e-3 * peak);
    }
    previous = peak;
  }
}

TEST(SweepAxes, BadAxesStopBeforeAnyOutput) {
  const struct {
    const char *axis, *expected;
  } cases[] = {
      {"Simulation/No such entry = 1; 2", "Sweep/Axis 1"},
      {"Theta = 0.5", "Sweep/Axis 1"},
      {"Simulation/Time step = 0.001; 0.002", "Sweep/Time steps"},
      {"Simulation/Theta = 0.5; 2", "value '2'"},
      {"Simulation/Theta = 0.6; 0.6", "same point directory tag"},
  };
  int n = 0;
  for (const auto& c : cases) {
    const std::string name = "axes-bad-" + std::to_string(n++);
    const fs::path sweep = scene_file(
        name + ".prm", std::string("subsection Sweep\n  set Axis 1 = ") + c.axis + "\nend\n");
    const fs::path out = fs::current_path() / name;
    fs::remove_all(out);
    const auto s = run_plantar("sweep " + sweep.string() + " -o " + out.string());
    EXPECT_EQ(s.status, 1) << c.axis << "\n" << s.output;
    EXPECT_NE(s.output.find(c.expected), std::string::npos) << c.axis << "\n" << s.output;
    EXPECT_FALSE(fs::exists(out / "points")) << c.axis;
    EXPECT_FALSE(fs::exists(out / "sweep.csv")) << c.axis;
  }
}

} // namespace
