// plantar sweep as users run it: a 2 x 2 grid (E x nu) of short drops on a coarse FEM sole.
// Checked: the parallel sweep equals the serial one, each point equals a fresh `plantar run`
// of its scene file, and an interrupted sweep recomputes only the unfinished points.
#include "tests/apps/cli_test_utilities.h"

#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>
#include <string>
#include <sys/wait.h>
#include <vector>

namespace {

namespace fs = std::filesystem;

using plantar::test::Outcome;
using plantar::test::read_text;
using plantar::test::summary_value;
Outcome run(const std::string& arguments) {
  return plantar::test::run_plantar(arguments);
}

/// The drop scene, FEM sole of 5 cm cells, 0.08 s (the impact is at 0.045 s), E x nu = 2 x 2.
fs::path tiny_sweep_scene() {
  const fs::path path = fs::current_path() / "tiny-sweep.prm";
  std::ofstream(path) << read_text(std::string(PLANTAR_SOURCE_DIR) + "/scenes/drop.prm")
                      << "subsection Robot\n  set Foot form = fem sole\nend\n"
                         "subsection Sole\n  set Mesh size = 0.05\nend\n"
                         "subsection Simulation\n  set Duration = 0.08\nend\n"
                         "subsection Sweep\n  set Young's moduli = 2e6, 8e6\n"
                         "  set Poisson ratios = 0.1, 0.45\nend\n";
  return path;
}

/// sweep.csv as id -> max_waist_acceleration_z ("status" must be ok).
std::map<std::string, double> sweep_results(const fs::path& directory) {
  std::ifstream in(directory / "sweep.csv");
  std::string line;
  std::getline(in, line);
  EXPECT_EQ(line.rfind("id,foot_form,time_step,E,nu,status,max_waist_acceleration_z", 0), 0u);
  std::map<std::string, double> results;
  while (std::getline(in, line)) {
    std::vector<std::string> cells;
    std::stringstream fields(line);
    std::string cell;
    while (std::getline(fields, cell, ','))
      cells.push_back(cell);
    EXPECT_GE(cells.size(), 7u) << line;
    if (cells.size() < 7)
      continue;
    EXPECT_EQ(cells[5], "ok") << line;
    results[cells[0]] = cells[5] == "ok" ? std::stod(cells[6]) : NAN;
  }
  return results;
}

const char* const ids[] = {"fem_sole_dt1ms_E2MPa_nu0.1", "fem_sole_dt1ms_E2MPa_nu0.45",
                           "fem_sole_dt1ms_E8MPa_nu0.1", "fem_sole_dt1ms_E8MPa_nu0.45"};

TEST(Sweep, ParallelEqualsSerialAndFreshRunsAndResumes) {
  const fs::path scene = tiny_sweep_scene();
  const fs::path parallel = fs::current_path() / "sweep-parallel";
  const fs::path serial = fs::current_path() / "sweep-serial";
  fs::remove_all(parallel);
  fs::remove_all(serial);

  const auto p = run("sweep " + scene.string() + " -o " + parallel.string() + " -j 2");
  std::printf("%s", p.output.c_str());
  ASSERT_EQ(p.status, 0) << p.output;
  EXPECT_NE(p.output.find("4 points, 0 already done, 4 to run with 2 processes"),
            std::string::npos);
  const auto s = run("sweep " + scene.string() + " -o " + serial.string() + " -j 1");
  ASSERT_EQ(s.status, 0) << s.output;
  const auto a = sweep_results(parallel), b = sweep_results(serial);
  ASSERT_EQ(a.size(), 4u);
  ASSERT_EQ(b.size(), 4u);
  for (const char* id : ids) {
    ASSERT_TRUE(a.count(id)) << id;
    // Same binary, same inputs: identical to round-off.
    EXPECT_NEAR(a.at(id), b.at(id), 1e-12 * std::abs(a.at(id))) << id;
    // The sole's material reached the run: each point differs from the others.
    for (const char* other : ids) {
      if (std::string(other) != id) {
        EXPECT_GT(std::abs(a.at(id) - a.at(other)), 1e-6 * a.at(id)) << id << " vs " << other;
      }
    }
  }
  // The point scene holds the material of its id.
  const std::string point_scene = read_text(parallel / "points" / ids[3] / "scene.prm");
  EXPECT_NE(point_scene.find("E=8000000, nu=0.45"), std::string::npos) << point_scene;

  // A fresh `plantar run` of one point's scene gives the sweep's number.
  const fs::path fresh = fs::current_path() / "sweep-fresh";
  fs::remove_all(fresh);
  const auto f = run("run " + (parallel / "points" / ids[2] / "scene.prm").string() + " -o " +
                     fresh.string() + " --no-figures");
  ASSERT_EQ(f.status, 0) << f.output;
  const double fresh_peak = summary_value(fresh / "summary.csv", "max_waist_acceleration_z");
  std::printf("point %s: sweep %.17g, fresh run %.17g m/s^2\n", ids[2], a.at(ids[2]), fresh_peak);
  EXPECT_NEAR(fresh_peak, a.at(ids[2]), 1e-12 * fresh_peak);

  // Interrupted sweep: one point unfinished (its summary.csv removed), one point finished
  // with a marker value. Only the unfinished point is recomputed; the marker survives.
  fs::remove(parallel / "points" / ids[0] / "summary.csv");
  const fs::path marked = parallel / "points" / ids[1] / "summary.csv";
  std::string text = read_text(marked);
  const std::string key = "max_waist_acceleration_z,";
  const auto at = text.find(key);
  ASSERT_NE(at, std::string::npos);
  text.replace(at + key.size(), text.find('\n', at) - at - key.size(), "12345");
  std::ofstream(marked) << text;
  const auto r = run("sweep " + scene.string() + " -o " + parallel.string() + " -j 2");
  std::printf("%s", r.output.c_str());
  ASSERT_EQ(r.status, 0) << r.output;
  EXPECT_NE(r.output.find("4 points, 3 already done, 1 to run"), std::string::npos);
  const auto c = sweep_results(parallel);
  EXPECT_EQ(c.at(ids[1]), 12345.0);                              // not recomputed
  EXPECT_NEAR(c.at(ids[0]), a.at(ids[0]), 1e-12 * a.at(ids[0])); // recomputed, same value
  EXPECT_EQ(c.at(ids[2]), a.at(ids[2]));
  EXPECT_TRUE(fs::exists(parallel / "figures" / "sweep_E_nu.png"));
  EXPECT_TRUE(fs::exists(parallel / "parameters.prm"));
}

TEST(Sweep, BadUsageAndScenes) {
  EXPECT_EQ(run("sweep --help").status, 0);
  EXPECT_EQ(run("sweep").status, 2);
  const fs::path scene = tiny_sweep_scene();
  const auto jobs = run("sweep " + scene.string() + " -j 0");
  EXPECT_EQ(jobs.status, 2);
  EXPECT_NE(jobs.output.find("-j 0: must be an integer in [1, 256]"), std::string::npos);
  // A static sole scene cannot be swept; nothing is written.
  const fs::path out = fs::current_path() / "sweep-static";
  fs::remove_all(out);
  const auto statics = run("sweep " + std::string(PLANTAR_SOURCE_DIR) +
                           "/scenes/static_sole.prm -o " + out.string());
  EXPECT_EQ(statics.status, 1);
  EXPECT_NE(statics.output.find("static_sole.prm"), std::string::npos) << statics.output;
  EXPECT_NE(statics.output.find("needs a humanoid scene"), std::string::npos) << statics.output;
  EXPECT_FALSE(fs::exists(out));
  // Out-of-range grid values name the entry, the value and the range.
  const fs::path bad = fs::current_path() / "bad-sweep.prm";
  std::ofstream(bad) << "set Scene type = drop\nsubsection Sweep\n  set Poisson ratios = 0.3, "
                        "0.5\nend\n";
  const auto nu = run("sweep " + bad.string() + " -o " + out.string());
  EXPECT_EQ(nu.status, 1);
  for (const char* part : {"bad-sweep.prm", "Sweep/Poisson ratios", "0.5", "(-1, 0.5)"})
    EXPECT_NE(nu.output.find(part), std::string::npos) << part << ": " << nu.output;
  EXPECT_FALSE(fs::exists(out));
}

} // namespace
