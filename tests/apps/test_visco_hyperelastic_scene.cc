// Viscous branches on the humanoid scenes' hyperelastic sole (issue 24): a bad branch value is
// refused before anything is written, naming the region, the key, its value and the range
// (the sole itself: test_visco_hyperelastic_drop.cc).
#include "tests/apps/cli_test_utilities.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

namespace {

namespace fs = std::filesystem;
using plantar::test::run_plantar;

/// scenes/drop_nonlinear.prm with Sole/Materials replaced by @p materials.
fs::path scene_file(const std::string& name, const std::string& materials) {
  std::ifstream in(std::string(PLANTAR_SOURCE_DIR) + "/scenes/drop_nonlinear.prm");
  std::stringstream text;
  text << in.rdbuf();
  const fs::path path = fs::current_path() / name;
  std::ofstream(path) << text.str() << "subsection Sole\n  set Materials = " << materials
                      << "\nend\n";
  return path;
}

TEST(ViscoHyperelasticScene, BadBranchValueIsRefused) {
  const fs::path out = fs::current_path() / "visco-hyperelastic-out";
  fs::remove_all(out);
  const auto bad =
      run_plantar("run " +
                  scene_file("visco-hyperelastic-bad.prm",
                             "rubber: law=neo_hookean, E=4e6, nu=0.3, beta1=-1.0, tau1=0.01")
                      .string() +
                  " -o " + out.string());
  std::printf("%s", bad.output.c_str());
  EXPECT_EQ(bad.status, 1);
  EXPECT_NE(bad.output.find("region 'rubber'"), std::string::npos);
  EXPECT_NE(bad.output.find("beta1 = -1 is out of range: allowed [0, inf)"), std::string::npos);
  EXPECT_FALSE(fs::exists(out));
}

} // namespace
