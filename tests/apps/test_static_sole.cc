// The default scene's figures against independent bounds: the sole (top
// bonded, bottom free) under a uniform pressure p = F / A compresses by
// p t / M <= delta <= p t / E (uniaxial strain .. uniaxial stress), the
// reaction on the attached face balances F, and the .vtu holds the fields.
#include "apps/static_sole_job.h"

#include <gtest/gtest.h>

#include <fstream>
#include <sstream>

namespace plantar::app {
namespace {

TEST(StaticSole, DefaultSceneAgainstBounds) {
  dealii::ParameterHandler prm;
  const Scene scene = load_scene(std::string(PLANTAR_SOURCE_DIR) + "/scenes/static_sole.prm", prm);
  const auto out = std::filesystem::current_path() / "out-static";
  const auto result = run_static_sole(scene, out);
  const double E = 4e6, nu = 0.3, t = scene.sole.thickness;
  const double p = scene.static_load.normal_force / (scene.sole.length * scene.sole.width);
  const double M = E * (1 - nu) / ((1 + nu) * (1 - 2 * nu));
  std::printf("mean bottom u_z = %.4e m in [%.4e, %.4e]; max |u| = %.4e m; reaction %.9f N\n",
              result.mean_bottom_uz, p * t / M, p * t / E, result.max_displacement,
              result.reaction_z);
  EXPECT_GT(result.mean_bottom_uz, p * t / M);
  EXPECT_LT(result.mean_bottom_uz, p * t / E);
  EXPECT_NEAR(result.reaction_z, -scene.static_load.normal_force, 1e-8 * 600);

  std::ifstream vtu(out / "sole.vtu");
  std::stringstream text;
  text << vtu.rdbuf();
  for (const char* array :
       {"Name=\"displacement\" NumberOfComponents=\"3\"",
        "Name=\"strain\" NumberOfComponents=\"9\"", "Name=\"stress\" NumberOfComponents=\"9\"",
        "Name=\"von_mises\"", "Name=\"material_id\""})
    EXPECT_NE(text.str().find(array), std::string::npos) << array;
}

} // namespace
} // namespace plantar::app
