// plantar sweep's relaxation-time axis (Sweep/Relaxation times, issue 24): a 2-point sweep over
// tau1 of the viscoelastic drop (scenes/visco_drop.prm, FEM sole of 5 cm cells, 0.08 s: the
// impact at 0.045 s) gives, per point, the peak waist acceleration and the soles' dissipated
// energy of a `plantar run` of the scene with tau1 written by hand; the two points differ.
// A relaxation time on an elastic sole is refused naming the parameter.
#include "tests/apps/cli_test_utilities.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <regex>
#include <sstream>
#include <string>
#include <utility>

namespace {

namespace fs = std::filesystem;

using plantar::test::read_text;
using plantar::test::run_plantar;
using plantar::test::summary_value;

/// scenes/visco_drop.prm shortened and coarsened, with @p tail appended.
fs::path scene_file(const std::string& name, const std::string& tail) {
  const fs::path path = fs::current_path() / name;
  std::ofstream(path) << read_text(std::string(PLANTAR_SOURCE_DIR) + "/scenes/visco_drop.prm")
                      << "subsection Sole\n  set Mesh size = 0.05\nend\n"
                         "subsection Simulation\n  set Duration = 0.08\nend\n"
                      << tail;
  return path;
}

/// The scene's Sole/Materials with tau1 set to @p tau, as a user edits it.
std::string materials_with_tau(const std::string& tau) {
  const std::string scene = read_text(std::string(PLANTAR_SOURCE_DIR) + "/scenes/visco_drop.prm");
  std::smatch match;
  EXPECT_TRUE(std::regex_search(scene, match, std::regex("set Materials = (.*)")));
  return std::regex_replace(match[1].str(), std::regex("tau1=[0-9.e-]+"), "tau1=" + tau);
}

TEST(SweepRelaxation, TwoPointsEqualTheSingleRuns) {
  const fs::path sweep =
      scene_file("visco-sweep.prm", "subsection Sweep\n  set Relaxation times = 1e-3, 2e-2\nend\n");
  const fs::path out = fs::current_path() / "visco-sweep";
  fs::remove_all(out);
  const auto s = run_plantar("sweep " + sweep.string() + " -o " + out.string() + " -j 2");
  std::printf("%s", s.output.c_str());
  ASSERT_EQ(s.status, 0) << s.output;
  const std::string csv = read_text(out / "sweep.csv");
  EXPECT_NE(csv.find("tau1,sole_dissipated_energy"), std::string::npos) << csv;
  double previous = NAN;
  const std::pair<const char*, const char*> points[] = {{"1e-3", "fem_sole_dt1ms_tau1ms"},
                                                        {"2e-2", "fem_sole_dt1ms_tau20ms"}};
  for (const auto& [tau, id] : points) {
    const fs::path point = out / "points" / id / "summary.csv";
    ASSERT_TRUE(fs::exists(point)) << id << "\n" << csv;
    const fs::path single =
        scene_file(std::string("visco-single-") + tau + ".prm",
                   "subsection Sole\n  set Materials = " + materials_with_tau(tau) + "\nend\n");
    const fs::path single_out = fs::current_path() / (std::string("visco-single-") + tau);
    fs::remove_all(single_out);
    const auto r =
        run_plantar("run " + single.string() + " -o " + single_out.string() + " --no-figures");
    ASSERT_EQ(r.status, 0) << r.output;
    for (const char* name : {"max_waist_acceleration_z", "sole_dissipated_energy"}) {
      const double a = summary_value(point, name),
                   b = summary_value(single_out / "summary.csv", name);
      std::printf("tau1 = %s s: %s sweep %.10e, single run %.10e\n", tau, name, a, b);
      EXPECT_NEAR(a, b, 1e-12 * std::abs(b)) << tau << " " << name;
    }
    const double dissipated = summary_value(point, "sole_dissipated_energy");
    EXPECT_GT(dissipated, 0) << tau;
    if (!std::isnan(previous)) { // the axis reached the material
      EXPECT_GT(std::abs(dissipated - previous), 1e-3 * dissipated);
    }
    previous = dissipated;
  }
}

TEST(SweepRelaxation, ElasticSoleRefusesTheAxis) {
  const fs::path sweep = scene_file("visco-sweep-elastic.prm",
                                    "subsection Sole\n  set Materials = rubber: law=linear, E=4e6, "
                                    "nu=0.3\nend\nsubsection Sweep\n  set Relaxation times = "
                                    "1e-3\nend\n");
  const fs::path out = fs::current_path() / "visco-sweep-elastic";
  fs::remove_all(out);
  const auto s = run_plantar("sweep " + sweep.string() + " -o " + out.string());
  EXPECT_EQ(s.status, 1) << s.output;
  EXPECT_NE(s.output.find("Sweep/Relaxation times"), std::string::npos) << s.output;
}

} // namespace
