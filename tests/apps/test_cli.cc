// The plantar program as users run it: help, parameter listing, the default
// scene, and one clear error with a non-zero exit and no output files for
// each kind of bad scene.
#include "apps/scene.h"

#include "tests/apps/cli_test_utilities.h"

#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <sys/wait.h>
#include <vector>

namespace {

using plantar::test::Outcome;
using plantar::test::summary_value;
Outcome run(const std::string& arguments) {
  return plantar::test::run_plantar(arguments);
}

std::filesystem::path write_scene(const std::string& name, const std::string& text) {
  const auto path = std::filesystem::current_path() / (name + ".prm");
  std::ofstream(path) << text;
  return path;
}

TEST(Cli, Help) {
  const auto help = run("--help");
  EXPECT_EQ(help.status, 0);
  EXPECT_NE(help.output.find("plantar run SCENE.prm"), std::string::npos);
  EXPECT_EQ(run("run --help").status, 0);
  EXPECT_EQ(run("print-parameters --help").status, 0);
  EXPECT_EQ(run("frobnicate").status, 2);
  for (const char* command : {"sweep", "plot"}) {
    const auto h = run(std::string(command) + " --help");
    EXPECT_EQ(h.status, 0) << command;
    EXPECT_NE(h.output.find(std::string("plantar ") + command), std::string::npos) << command;
    EXPECT_NE(help.output.find(std::string("plantar ") + command), std::string::npos) << command;
  }
  EXPECT_EQ(run("plot").status, 2);
}

/// The default scene is the walking comparison: scenes/walk.prm's parameters in the well-posed
/// setting (stabilizer, foot damping rate 12 /s, F/T low-pass 25 Hz, touchdowns at 0.1 m/s,
/// dt 0.5 ms, theta 1/2), all three forms.
TEST(Cli, DefaultSceneIsTheWalkComparisonOfWalkPrm) {
  dealii::ParameterHandler default_prm, walk_prm;
  const auto source = std::string(PLANTAR_SOURCE_DIR) + "/scenes/";
  const auto comparison = plantar::app::load_scene(source + "default.prm", default_prm);
  plantar::app::load_scene(source + "walk.prm", walk_prm);
  const std::vector<std::array<const char*, 3>> well_posed{
      {"Control", "Stabilizer", "dcm"},
      {"Control", "Foot damping rate", "12"},
      {"Control", "Force sensor bandwidth", "25"},
      {"Walking", "Touchdown velocity", "0.1"},
      {"Simulation", "Time step", "0.0005"},
      {"Simulation", "Theta", "0.5"}};
  for (const auto& [section, entry, value] : well_posed) {
    walk_prm.enter_subsection(section);
    walk_prm.set(entry, value);
    walk_prm.leave_subsection();
  }
  ASSERT_EQ(comparison.robot.foot_forms.size(), 3u);
  EXPECT_EQ(comparison.type, plantar::app::SceneType::walk);
  default_prm.enter_subsection("Robot");
  default_prm.set("Foot forms", "");
  default_prm.leave_subsection();
  std::ostringstream a, b;
  default_prm.print_parameters(a, dealii::ParameterHandler::PRM);
  walk_prm.print_parameters(b, dealii::ParameterHandler::PRM);
  EXPECT_EQ(a.str(), b.str())
      << "scenes/default.prm must keep scenes/walk.prm's values but the well-posed setting";
}

/// PNG files: signature and a non-trivial size.
void expect_png(const std::filesystem::path& file) {
  std::ifstream in(file, std::ios::binary);
  char signature[8] = {};
  in.read(signature, 8);
  EXPECT_EQ(std::string(signature, 8), std::string("\x89PNG\r\n\x1a\n", 8)) << file;
  EXPECT_TRUE(std::filesystem::exists(file) && std::filesystem::file_size(file) > 1000) << file;
}

/// A URDF that urdfdom rejects (a truncated file) in a three-form comparison and in a sweep: one
/// message naming the file, exit 1, no output directory (the robot is loaded before any form or
/// point runs).
TEST(Cli, RejectedUrdfIsReportedOnceBeforeAnyOutput) {
  std::ifstream full(std::string(PLANTAR_SOURCE_DIR) + "/models/hrp2/hrp2.urdf");
  std::stringstream urdf;
  urdf << full.rdbuf();
  const auto truncated = std::filesystem::current_path() / "truncated_robot.urdf";
  std::ofstream(truncated) << urdf.str().substr(0, urdf.str().size() / 2);
  std::ifstream in(std::string(PLANTAR_SOURCE_DIR) + "/scenes/drop.prm");
  std::stringstream text;
  text << in.rdbuf();
  const auto scene = write_scene(
      "truncated-urdf", text.str() + "subsection Robot\n  set URDF file = " + truncated.string() +
                            "\n  set Foot forms = rigid, compliant ankle, fem sole\nend\n");
  for (const char* command : {"run", "sweep"}) {
    const auto out = std::filesystem::current_path() / (std::string("out-truncated-") + command);
    std::filesystem::remove_all(out);
    const auto result = run(std::string(command) + " " + scene.string() + " -o " + out.string());
    std::printf("%s: exit %d: %s", command, result.status, result.output.c_str());
    EXPECT_EQ(result.status, 1) << command;
    std::size_t n = 0;
    for (std::size_t at = result.output.find("truncated_robot.urdf"); at != std::string::npos;
         at = result.output.find("truncated_robot.urdf", at + 1))
      ++n;
    EXPECT_GE(n, 1u) << command;
    EXPECT_EQ(result.output.find("plantar: error"), result.output.rfind("plantar: error"))
        << command << ": one error message";
    EXPECT_EQ(result.output.find("FAILED"), std::string::npos) << command;
    EXPECT_FALSE(std::filesystem::exists(out)) << command << " left output behind";
  }
}

/// A comparison of two forms on a 0.4 s drop where the compliant ankle is made to fail (a
/// 1 N/m ankle spring without damper: the robot falls through its ankles onto the Fall height).
TEST(Cli, ComparisonRunsEachFormReportsFailuresAndPlots) {
  const std::string drop = std::string(PLANTAR_SOURCE_DIR) + "/scenes/drop.prm";
  std::ifstream in(drop);
  std::stringstream text;
  text << in.rdbuf();
  const std::string common = text.str() + "subsection Simulation\n  set Duration = 0.4\nend\n" +
                             "subsection Output\n  set Write VTU = false\nend\n" +
                             "subsection Robot\n  set Ankle linear stiffness = 1\n" +
                             "  set Ankle linear damping = 0\n";
  const auto scene =
      write_scene("comparison", common + "  set Foot forms = rigid, compliant ankle\nend\n");
  const auto out = std::filesystem::current_path() / "out-comparison";
  std::filesystem::remove_all(out);
  const auto result = run("run " + scene.string() + " -o " + out.string());
  std::printf("%s", result.output.c_str());
  EXPECT_EQ(result.status, 1);
  for (const char* part : {"foot forms failed", "compliant ankle", "fell", "FAILED"})
    EXPECT_NE(result.output.find(part), std::string::npos) << part;
  EXPECT_TRUE(std::filesystem::exists(out / "parameters.prm"));
  EXPECT_TRUE(std::filesystem::exists(out / "summary.txt"));
  EXPECT_TRUE(std::filesystem::exists(out / "compliant_ankle" / "failure.txt"));
  EXPECT_FALSE(std::filesystem::exists(out / "compliant_ankle" / "summary.csv"));

  // The failed form's CSV stops at the fall: free fall of the waist from its start height to
  // Fall height = 0.4 m, t = sqrt(2 (z0 - 0.4) / g), the feet's stop being negligible.
  std::ifstream waist(out / "compliant_ankle" / "failed" / "waist.csv");
  std::string line, first, last;
  std::getline(waist, line);
  std::getline(waist, first);
  last = first;
  while (std::getline(waist, line))
    last = line;
  const double z0 =
      std::stod(first.substr(first.find(',', first.find(',', first.find(',') + 1) + 1) + 1));
  const double t_end = std::stod(last.substr(0, last.find(',')));
  const double t_fall = std::sqrt(2 * (z0 - 0.4) / 9.81);
  std::printf("compliant ankle fell at t = %.3f s; free fall from z0 = %.4f m: %.3f s\n", t_end, z0,
              t_fall);
  EXPECT_NEAR(t_end, t_fall, 0.05 * t_fall);

  // The rigid form equals a single run of the same scene with Foot form = rigid.
  const auto single = write_scene("comparison-rigid", common + "  set Foot form = rigid\nend\n");
  const auto single_out = std::filesystem::current_path() / "out-comparison-rigid";
  std::filesystem::remove_all(single_out);
  const auto single_result = run("run " + single.string() + " -o " + single_out.string());
  ASSERT_EQ(single_result.status, 0) << single_result.output;
  const double a = summary_value(out / "rigid" / "summary.csv", "max_waist_acceleration_z");
  const double b = summary_value(single_out / "summary.csv", "max_waist_acceleration_z");
  std::printf("rigid drop peak: comparison %.17g, single run %.17g m/s^2\n", a, b);
  EXPECT_NEAR(a, b, 1e-12 * b);
  EXPECT_GT(a, 10.0); // an impact, not the 9.81 of free fall

  // Figures of both forms (the failed one up to its failure), and of the single run.
  for (const char* name : {"waist_z.png", "waist_velocity_z.png", "waist_acceleration_z.png",
                           "right_knee_torque.png"}) {
    expect_png(out / "figures" / name);
    expect_png(single_out / "figures" / name);
  }
  // plantar plot redraws them; a directory without CSV gives one message and exit 1.
  std::filesystem::remove_all(out / "figures");
  const auto plot = run("plot " + out.string());
  EXPECT_EQ(plot.status, 0) << plot.output;
  expect_png(out / "figures" / "waist_acceleration_z.png");
  const auto empty = std::filesystem::current_path() / "out-empty";
  std::filesystem::create_directories(empty);
  const auto no_csv = run("plot " + empty.string());
  EXPECT_EQ(no_csv.status, 1);
  EXPECT_NE(no_csv.output.find("no CSV outputs in '" + empty.string() + "'"), std::string::npos)
      << no_csv.output;
  EXPECT_FALSE(std::filesystem::exists(empty / "figures"));
}

/// The progress bar is drawn on a terminal only: through a pipe the output has no carriage
/// return; under `script` (a pseudo-terminal) it shows the simulated time and real-time factor.
TEST(Cli, ProgressBarOnlyOnATerminal) {
  const std::string drop = std::string(PLANTAR_SOURCE_DIR) + "/scenes/drop.prm";
  std::ifstream in(drop);
  std::stringstream text;
  text << in.rdbuf();
  const auto scene =
      write_scene("progress", text.str() + "subsection Simulation\n  set Duration = 0.3\nend\n"
                                           "subsection Output\n  set Write VTU = false\nend\n");
  const auto out = std::filesystem::current_path() / "out-progress";
  const auto piped = run("run " + scene.string() + " -o " + out.string() + " --no-figures");
  ASSERT_EQ(piped.status, 0) << piped.output;
  EXPECT_EQ(piped.output.find('\r'), std::string::npos);
  EXPECT_EQ(piped.output.find("real-time factor"), std::string::npos);
  // The same run on a pseudo-terminal.
  const std::string command = "script -qfec '" + std::string(PLANTAR_BINARY) + " run " +
                              scene.string() + " -o " + out.string() +
                              " --no-figures' /dev/null 2>&1";
  FILE* pipe = ::popen(command.c_str(), "r");
  std::string output;
  std::array<char, 4096> buffer;
  while (std::fgets(buffer.data(), buffer.size(), pipe))
    output += buffer.data();
  EXPECT_EQ(::pclose(pipe), 0) << output;
  EXPECT_NE(output.find("real-time factor"), std::string::npos) << output;
  EXPECT_NE(output.find("t = 0.300 / 0.300 s"), std::string::npos) << output;
}

TEST(Cli, PrintParametersListsDefaultsRangesHelp) {
  const auto listing = run("print-parameters");
  EXPECT_EQ(listing.status, 0);
  for (const char* expected :
       {"Thickness = 0.020", "Element degree = 1", "[Integer range 1...2 (inclusive)]",
        "Materials = rubber: E=4e6, nu=0.3", "-1 < nu < 0.5", "Total normal force = 600"})
    EXPECT_NE(listing.output.find(expected), std::string::npos) << expected;
  // The --prm form is itself a valid scene.
  const auto prm = run("print-parameters --prm");
  const auto scene = write_scene("defaults", prm.output);
  const auto out = std::filesystem::current_path() / "out-defaults";
  std::filesystem::remove_all(out);
  const auto result = run("run " + scene.string() + " -o " + out.string());
  EXPECT_EQ(result.status, 0) << result.output;
}

TEST(Cli, StaticSoleSceneWritesItsOutputs) {
  const auto out = std::filesystem::current_path() / "out-static-sole";
  std::filesystem::remove_all(out);
  const auto result =
      run("run " + std::string(PLANTAR_SOURCE_DIR) + "/scenes/static_sole.prm -o " + out.string());
  ASSERT_EQ(result.status, 0) << result.output;
  EXPECT_NE(result.output.find("maximum displacement"), std::string::npos);
  for (const char* file : {"parameters.prm", "summary.txt", "sole.vtu"})
    EXPECT_TRUE(std::filesystem::exists(out / file)) << file;
  // The parameter set written is complete: it runs again to the same summary.
  const auto again = run("run " + (out / "parameters.prm").string() + " -o " +
                         (std::filesystem::current_path() / "out-again").string());
  ASSERT_EQ(again.status, 0) << again.output;
  const auto max_line = [](const std::string& text) {
    return text.substr(text.find("maximum displacement"), 40);
  };
  EXPECT_EQ(max_line(result.output), max_line(again.output));
}

TEST(Cli, HumanoidSceneWritesCsvAndFailuresStopWithStepAndTime) {
  const std::string drop = std::string(PLANTAR_SOURCE_DIR) + "/scenes/drop.prm";
  std::ifstream in(drop);
  std::stringstream text;
  text << in.rdbuf();
  const auto short_drop =
      write_scene("short-drop", text.str() + "subsection Simulation\n  set Duration = 0.2\nend\n");
  const auto out = std::filesystem::current_path() / "out-drop";
  std::filesystem::remove_all(out);
  const auto result = run("run " + short_drop.string() + " -o " + out.string());
  ASSERT_EQ(result.status, 0) << result.output;
  std::printf("%s", result.output.c_str());
  for (const char* file :
       {"parameters.prm", "summary.txt", "waist.csv", "joints.csv", "contacts.csv"})
    EXPECT_TRUE(std::filesystem::exists(out / file)) << file;
  // Headers name the quantities; 200 steps written one row each.
  const auto first_line = [](const std::filesystem::path& file, int* n_lines) {
    std::ifstream csv(file);
    std::string header, line;
    std::getline(csv, header);
    *n_lines = 0;
    while (std::getline(csv, line))
      ++*n_lines;
    return header;
  };
  int n = 0;
  EXPECT_NE(first_line(out / "waist.csv", &n).find("t,x,y,z,vx,vy,vz,ax,ay,az"), std::string::npos);
  EXPECT_EQ(n, 200);
  const std::string joints = first_line(out / "joints.csv", &n);
  for (const char* column : {"RLEG_JOINT3_q", "RLEG_JOINT3_ref", "RLEG_JOINT3_tau"})
    EXPECT_NE(joints.find(column), std::string::npos) << column;
  EXPECT_NE(first_line(out / "contacts.csv", &n).find("right_fz,right_copx,right_copy"),
            std::string::npos);

  // A fall (waist required above 0.9 m, it starts at about 0.72 m) stops at the first step.
  const auto falling =
      write_scene("falling", text.str() + "subsection Simulation\n  set Fall height = 0.9\nend\n");
  const auto out_fall = std::filesystem::current_path() / "out-falling";
  std::filesystem::remove_all(out_fall);
  const auto fell = run("run " + falling.string() + " -o " + out_fall.string());
  std::printf("fall: exit %d: %s", fell.status, fell.output.c_str());
  EXPECT_EQ(fell.status, 1);
  for (const char* part : {"falling.prm", "step 1, t = 0.001 s", "fell", "Fall height"})
    EXPECT_NE(fell.output.find(part), std::string::npos) << part;
  EXPECT_FALSE(std::filesystem::exists(out_fall / "summary.txt"));

  // Bad humanoid parameters: one clear error each.
  const auto form = write_scene("bad-form", "subsection Robot\n  set Foot form = paper\nend\n");
  const auto bad_form = run("run " + form.string());
  EXPECT_EQ(bad_form.status, 1);
  EXPECT_NE(bad_form.output.find("Foot form"), std::string::npos) << bad_form.output;
  const auto steps = write_scene(
      "bad-steps", "set Scene type = walk\nsubsection Walking\n  set Footsteps = 0.1, x\nend\n");
  const auto bad_steps = run("run " + steps.string());
  std::printf("bad footsteps: %s", bad_steps.output.c_str());
  EXPECT_EQ(bad_steps.status, 1);
  for (const char* part : {"bad-steps.prm", "Walking/Footsteps", "0.1, x", "x, y, yaw"})
    EXPECT_NE(bad_steps.output.find(part), std::string::npos) << part;
}

struct BadScene {
  const char* name;
  const char* text;
  std::vector<const char*> expected;
};

TEST(Cli, BadScenesGiveOneClearErrorAndNoOutput) {
  const BadScene cases[] = {
      {"unknown", "set Foo = 1\n", {"Foo", "Line <1>"}},
      {"negative",
       "subsection Sole\n  set Thickness = -0.01\nend\n",
       {"Thickness", "-0.01", "Double 0...0.5"}},
      {"huge",
       "subsection Sole\n  set Thickness = 1e308\nend\n",
       {"Thickness", "1e308", "0...0.5"}},
      {"cells",
       "subsection Sole\n  set Mesh size = 0.0002\nend\n",
       {"Sole/Mesh size", "0.0002", "cells", "allowed up to 2e+06"}},
      {"pad-name",
       "subsection Pad 1\n  set Link = RLEG_LINK3\n  set Name = a,b\nend\n",
       {"Pad 1/Name", "a,b", "letters, digits"}},
      {"zero", "subsection Sole\n  set Thickness = 0\nend\n", {"Sole/Thickness", "= 0", "> 0"}},
      {"nu",
       "subsection Sole\n  set Materials = rubber: E=4e6, nu=0.6\nend\n",
       {"Sole/Materials", "0.6", "-1 < nu < 0.5"}},
      {"young",
       "subsection Sole\n  set Materials = rubber: E=-1, nu=0.3\nend\n",
       {"Sole/Materials", "-1", "E must be > 0"}},
      {"geo",
       "subsection Sole\n  set Geometry file = nowhere.geo\nend\n",
       {"Geometry file", "nowhere.geo", "no such file"}},
      {"region",
       "subsection Sole\n  set Materials = heel: E=4e6, nu=0.3\nend\n",
       {"Sole/Materials", "heel", "sole_box.geo"}},
      {"degree",
       "subsection Sole\n  set Element degree = 3\nend\n",
       {"Element degree", "3", "Integer range 1...2"}},
      {"syntax", "garbage line\n", {"garbage line", "could not be parsed"}},
      {"forms",
       "subsection Robot\n  set Foot forms = rigid, paper\nend\n",
       {"Foot forms", "rigid, paper", "rigid|compliant ankle|fem sole"}},
      {"urdf",
       "subsection Robot\n  set URDF file = nowhere.urdf\nend\n",
       {"Robot/URDF file", "nowhere.urdf", "no such file"}},
      {"sweep-e",
       "subsection Sweep\n  set Young's moduli = 1e6, -2\nend\n",
       {"Sweep/Young's moduli", "-2", "> 0"}},
      {"theta",
       "subsection Simulation\n  set Theta = 0.4\nend\n",
       {"Theta", "0.4", "Double 0.5...1"}},
      {"damping-hyper",
       "subsection Sole\n  set Model = hyperelastic\n  set Materials = rubber: law=neo_hookean, "
       "E=4e6, nu=0.3\n  set Damping time = 0.001\nend\n",
       {"Sole/Damping time", "0.001", "linear model only"}},
      {"sweep-dt",
       "subsection Sweep\n  set Time steps = 0.001, 0.5\nend\n",
       {"Sweep/Time steps", "0.5", "(0, 0.01]"}},
      {"sweep-skip",
       "subsection Contact\n  set Sweep skip fraction = 1\nend\n",
       {"Contact/Sweep skip fraction", "= 1", "in [0, 1)"}},
      {"failure-residual",
       "subsection Contact\n  set Failure residual = 0.5 x Tolerance\nend\n",
       {"Contact/Failure residual", "0.5 x Tolerance", "'k x Tolerance' (k >= 1)"}},
      {"failure-residual-nan",
       "subsection Contact\n  set Failure residual = nan\nend\n",
       {"Contact/Failure residual", "nan", "in m/s (> 0)"}},
      {"min-jacobian",
       "subsection Sole\n  set Min jacobian = 0\nend\n",
       {"Sole/Min jacobian", "0", "in (0, 1)"}},
      // Found by tests/apps/fuzz_scenes.py: both crashed the run (SIGSEGV) before their bounds.
      {"duration",
       "subsection Simulation\n  set Duration = 1e308\nend\n",
       {"Duration", "1e308", "0...3600"}},
      {"hold-time",
       "set Scene type = lean\nsubsection Lean\n  set Hold time = 1e308\nend\n",
       {"Hold time", "1e308", "600"}},
  };
  for (const auto& c : cases) {
    const auto scene = write_scene(std::string("bad-") + c.name, c.text);
    const auto out = std::filesystem::current_path() / (std::string("out-bad-") + c.name);
    std::filesystem::remove_all(out);
    const auto result = run("run " + scene.string() + " -o " + out.string());
    std::printf("%s: exit %d: %s", c.name, result.status, result.output.c_str());
    EXPECT_EQ(result.status, 1) << c.name;
    EXPECT_NE(result.output.find(scene.filename().string()), std::string::npos) << c.name;
    for (const char* part : c.expected)
      EXPECT_NE(result.output.find(part), std::string::npos) << c.name << ": " << part;
    EXPECT_FALSE(std::filesystem::exists(out)) << c.name << " left output behind";
  }
  const auto missing = run("run /nonexistent/scene.prm");
  EXPECT_EQ(missing.status, 1);
  EXPECT_NE(missing.output.find("/nonexistent/scene.prm"), std::string::npos);
}

} // namespace
