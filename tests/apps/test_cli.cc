// The plantar program as users run it: help, parameter listing, the default
// scene, and one clear error with a non-zero exit and no output files for
// each kind of bad scene.
#include <gtest/gtest.h>

#include <array>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <sys/wait.h>

namespace {

struct Outcome {
  int status;
  std::string output; // stdout and stderr
};

Outcome run(const std::string& arguments) {
  const std::string command = std::string(PLANTAR_BINARY) + " " + arguments + " 2>&1";
  FILE* pipe = ::popen(command.c_str(), "r");
  std::string output;
  std::array<char, 4096> buffer;
  while (std::fgets(buffer.data(), buffer.size(), pipe))
    output += buffer.data();
  const int status = ::pclose(pipe);
  return {WIFEXITED(status) ? WEXITSTATUS(status) : -1, output};
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

TEST(Cli, DefaultSceneWritesItsOutputs) {
  const auto out = std::filesystem::current_path() / "out-default";
  std::filesystem::remove_all(out);
  const auto result =
      run("run " + std::string(PLANTAR_SOURCE_DIR) + "/scenes/default.prm -o " + out.string());
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
       {"Thickness", "-0.01", "Double 0...MAX_DOUBLE"}},
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
