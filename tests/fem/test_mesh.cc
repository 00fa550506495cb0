// gmsh .geo -> MSH 2.2 -> deal.II: cell counts, physical groups (names,
// boundary ids, material ids), areas and volumes against the box's closed
// form, and the errors for a broken .geo, a missing file, a missing group
// and an empty mesh.
#include "fem/mesh_generator.h"
#include "fem/mesh_import.h"
#include "fem_test_utilities.h"

#include <deal.II/grid/grid_tools.h>
#include <gtest/gtest.h>

#include <unistd.h>

#include <chrono>
#include <cmath>
#include <filesystem>
#include <fstream>

namespace plantar::fem {
namespace {

constexpr double L = 0.2172, W = 0.138, T = 0.020;

MeshRequest sole_request(const std::string& geo, double mesh_size, bool hex) {
  MeshRequest request;
  request.geo_file = testing::source_path("meshes/" + geo);
  request.numbers = {{"SoleLength", L},
                     {"SoleWidth", W},
                     {"SoleThickness", T},
                     {"SoleMeshSize", mesh_size},
                     {"SoleHex", hex ? 1.0 : 0.0}};
  request.cache_directory = testing::test_cache_dir();
  return request;
}

double boundary_area(const dealii::Triangulation<3>& tria, dealii::types::boundary_id id) {
  double area = 0;
  for (const auto& cell : tria.active_cell_iterators())
    for (const auto& face : cell->face_iterators())
      if (face->at_boundary() && face->boundary_id() == id)
        area += face->measure();
  return area;
}

double region_volume(const dealii::Triangulation<3>& tria, dealii::types::material_id id) {
  double volume = 0;
  for (const auto& cell : tria.active_cell_iterators())
    if (cell->material_id() == id)
      volume += cell->measure();
  return volume;
}

class SoleMesh : public ::testing::TestWithParam<bool> {};

TEST_P(SoleMesh, GroupsAreasVolumes) {
  const bool hex = GetParam();
  const auto msh = generate_mesh(sole_request("sole_box.geo", 0.01, hex));
  dealii::Triangulation<3> tria;
  const auto groups = import_mesh(msh, {"top", "bottom", "sides"}, tria);
  EXPECT_EQ(cell_kind(tria), hex ? CellKind::hexahedron : CellKind::tetrahedron);
  if (hex) {
    EXPECT_EQ(tria.n_active_cells(), 22u * 14u * 2u); // ceil(L/h) x ceil(W/h) x ceil(T/h)
  }
  const double top = boundary_area(tria, groups.surface("top"));
  const double bottom = boundary_area(tria, groups.surface("bottom"));
  const double sides = boundary_area(tria, groups.surface("sides"));
  const double volume = region_volume(tria, groups.volume("rubber"));
  std::printf("%s sole: %u cells, top %.6e m^2, bottom %.6e m^2, sides %.6e m^2, volume %.6e m^3\n",
              hex ? "hex" : "tet", tria.n_active_cells(), top, bottom, sides, volume);
  EXPECT_NEAR(top / (L * W), 1.0, 1e-12);
  EXPECT_NEAR(bottom / (L * W), 1.0, 1e-12);
  EXPECT_NEAR(sides / (2 * (L + W) * T), 1.0, 1e-12);
  EXPECT_NEAR(volume / (L * W * T), 1.0, 1e-12);
  // Frame: top face at z = 0, bottom face at z = -T.
  for (const auto& cell : tria.active_cell_iterators())
    for (const auto& face : cell->face_iterators())
      if (face->at_boundary() && face->boundary_id() == groups.surface("top")) {
        EXPECT_NEAR(face->center()[2], 0.0, 1e-12);
      } else if (face->at_boundary() && face->boundary_id() == groups.surface("bottom")) {
        EXPECT_NEAR(face->center()[2], -T, 1e-12);
      }
}
INSTANTIATE_TEST_SUITE_P(TetAndHex, SoleMesh, ::testing::Values(false, true));

TEST(Mesh, TwoLayerRegions) {
  auto request = sole_request("sole_two_layer.geo", 0.01, true);
  request.numbers["TopFraction"] = 0.25;
  dealii::Triangulation<3> tria;
  const auto groups = import_mesh(generate_mesh(request), {"top", "bottom"}, tria);
  const double top_volume = region_volume(tria, groups.volume("top_layer"));
  const double bottom_volume = region_volume(tria, groups.volume("bottom_layer"));
  EXPECT_NEAR(top_volume / (0.25 * L * W * T), 1.0, 1e-12);
  EXPECT_NEAR(bottom_volume / (0.75 * L * W * T), 1.0, 1e-12);
}

TEST(Mesh, CacheReusesAndRegenerates) {
  const auto first = generate_mesh(sole_request("sole_box.geo", 0.02, true));
  const auto again = generate_mesh(sole_request("sole_box.geo", 0.02, true));
  const auto other = generate_mesh(sole_request("sole_box.geo", 0.03, true));
  EXPECT_EQ(first, again);
  EXPECT_NE(first, other);
}

std::string error_of(const std::function<void()>& f) {
  try {
    f();
  } catch (const std::exception& e) {
    return e.what();
  }
  return "";
}

TEST(MeshErrors, MissingGroupNamesFileAndGroup) {
  const auto msh = generate_mesh(sole_request("sole_box.geo", 0.02, true));
  dealii::Triangulation<3> tria;
  const std::string message = error_of([&] { import_mesh(msh, {"top", "heel"}, tria); });
  std::printf("message: %s\n", message.c_str());
  EXPECT_NE(message.find("heel"), std::string::npos);
  EXPECT_NE(message.find(msh.string()), std::string::npos);
}

TEST(MeshErrors, BrokenGeoNamesFile) {
  const auto geo = std::filesystem::current_path() / "broken.geo";
  std::ofstream(geo) << "Point(1) = {0, 0, 0;\nThis is not gmsh\n";
  MeshRequest request;
  request.geo_file = geo;
  request.cache_directory = testing::test_cache_dir();
  const std::string message = error_of([&] { generate_mesh(request); });
  std::printf("message: %s\n", message.substr(0, 200).c_str());
  EXPECT_NE(message.find("broken.geo"), std::string::npos);
  EXPECT_NE(message.find("gmsh failed"), std::string::npos);
  // No half-written mesh is left in the cache.
  for (const auto& entry : std::filesystem::directory_iterator(testing::test_cache_dir()))
    EXPECT_EQ(entry.path().string().find("broken"), std::string::npos) << entry.path();
}

// A sole 1000 times too large for its mesh size (a .geo in mm read as m): gmsh is stopped at
// the time limit, the error names the .geo and nothing is left in the cache.
TEST(MeshErrors, TimeLimitNamesFile) {
  MeshRequest request = sole_request("sole_box.geo", 0.002, false);
  request.numbers["SoleLength"] = 1000 * L;
  request.numbers["SoleWidth"] = 1000 * W;
  request.time_limit = 1;
  const auto start = std::chrono::steady_clock::now();
  const std::string message = error_of([&] { generate_mesh(request); });
  const double seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  std::printf("after %.2f s: %s\n", seconds, message.c_str());
  EXPECT_LT(seconds, 10.0);
  EXPECT_NE(message.find("sole_box.geo"), std::string::npos);
  EXPECT_NE(message.find("within 1 s"), std::string::npos);
  // Only this process's temporary files: tests running in parallel share the cache.
  const std::string own = ".tmp-" + std::to_string(::getpid());
  for (const auto& entry : std::filesystem::directory_iterator(testing::test_cache_dir()))
    EXPECT_EQ(entry.path().string().find(own), std::string::npos) << entry.path();
}

TEST(MeshErrors, MissingGeoNamesFile) {
  MeshRequest request;
  request.geo_file = "/nonexistent/sole.geo";
  request.cache_directory = testing::test_cache_dir();
  const std::string message = error_of([&] { generate_mesh(request); });
  EXPECT_NE(message.find("/nonexistent/sole.geo"), std::string::npos) << message;
}

TEST(MeshErrors, EmptyMeshNamesFile) {
  const auto msh = std::filesystem::current_path() / "empty.msh";
  std::ofstream(msh) << "$MeshFormat\n2.2 0 8\n$EndMeshFormat\n$Nodes\n0\n$EndNodes\n"
                        "$Elements\n0\n$EndElements\n";
  dealii::Triangulation<3> tria;
  const std::string message = error_of([&] { import_mesh(msh, {"top"}, tria); });
  std::printf("message: %s\n", message.substr(0, 200).c_str());
  EXPECT_NE(message.find("empty.msh"), std::string::npos);
}

} // namespace
} // namespace plantar::fem
