// The links of the ParaView series (apps/scene_vtk_links.h): a URDF with a <visual> box (yawed
// 90 deg), a sphere on a merged link, a <collision> cylinder, a link without geometry (sticks)
// and a link with three mesh visuals (a binary STL tetrahedron by relative path, scaled; an
// OBJ cube by file:// URI, scaled; an ASCII PLY triangle), written at a known configuration
// and read back with VTK's vtkXMLPolyDataReader. Every point is compared with its
// hand-computed world position; the mesh errors (package://, missing file, unsupported
// extension, empty file) name the URDF, the link and the mesh. (The series of a run read by
// VTK from Python: test_vtk_output.py.)

#include "apps/scene_vtk_links.h"

#include "multibody/kinematics.h"
#include "multibody/urdf_loader.h"

#include <vtkCell.h>
#include <vtkCellData.h>
#include <vtkDataArray.h>
#include <vtkNew.h>
#include <vtkPoints.h>
#include <vtkPolyData.h>
#include <vtkXMLPolyDataReader.h>

#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <functional>
#include <map>
#include <sstream>
#include <string>
#include <vector>

namespace {

using namespace plantar;
namespace fs = std::filesystem;

constexpr double r_stick = 0.01; // m
constexpr double tol = 1e-6;     // m: Float32 points within 4 m of the origin

/// The test robot; @p finger_visuals: the <visual> elements of link "finger".
std::string urdf_text(const std::string& finger_visuals) {
  const std::string inertial =
      R"(<inertial><mass value="1"/><inertia ixx="1" ixy="0" ixz="0" iyy="1" iyz="0" izz="1"/></inertial>)";
  return R"(<?xml version="1.0"?>
<robot name="vtk_links">
  <link name="base">)" +
         inertial + R"(
    <visual><origin xyz="0 0 0.1" rpy="0 0 1.5707963267948966"/>
      <geometry><box size="0.2 0.1 0.4"/></geometry></visual>
  </link>
  <joint name="head_joint" type="fixed"><parent link="base"/><child link="head"/>
    <origin xyz="0 0 0.5"/></joint>
  <link name="head">)" +
         inertial + R"(
    <visual><origin xyz="0.2 0 0"/><geometry><sphere radius="0.1"/></geometry></visual>
    <collision><geometry><box size="1 1 1"/></geometry></collision>
  </link>
  <joint name="j1" type="revolute"><parent link="base"/><child link="arm"/>
    <origin xyz="0 0 0.3"/><axis xyz="0 1 0"/>
    <limit lower="-3" upper="3" effort="10" velocity="1"/></joint>
  <link name="arm">)" +
         inertial + R"(
    <collision><origin xyz="0 0 0.25"/>
      <geometry><cylinder radius="0.05" length="0.5"/></geometry></collision>
  </link>
  <joint name="j2" type="revolute"><parent link="arm"/><child link="hand"/>
    <origin xyz="0 0 0.5"/><axis xyz="0 1 0"/>
    <limit lower="-3" upper="3" effort="10" velocity="1"/></joint>
  <link name="hand">)" +
         inertial + R"(</link>
  <joint name="tip_joint" type="fixed"><parent link="hand"/><child link="tip"/>
    <origin xyz="0.1 0 0"/></joint>
  <link name="tip"/>
  <joint name="j3" type="revolute"><parent link="hand"/><child link="finger"/>
    <origin xyz="0 0 0.2"/><axis xyz="0 1 0"/>
    <limit lower="-3" upper="3" effort="10" velocity="1"/></joint>
  <link name="finger">)" +
         inertial + finger_visuals + R"(</link>
</robot>)";
}

std::string mesh_visual(const std::string& filename, const std::string& scale,
                        const std::string& origin) {
  return "<visual><origin " + origin + "/><geometry><mesh filename=\"" + filename + "\" scale=\"" +
         scale + "\"/></geometry></visual>";
}

void write_text(const fs::path& path, const std::string& text) {
  fs::create_directories(path.parent_path());
  std::ofstream(path, std::ios::binary) << text;
}

/// A fresh directory with the URDF (finger: @p finger_visuals) and its meshes:
/// meshes/wedge.stl, the tetrahedron (0,0,0) (0.1,0,0) (0,0.05,0) (0,0,0.02) (binary STL),
/// cube.obj, the unit cube [0,1]^3 (8 vertices, 6 quads), and meshes/tri.ply, the triangle
/// (0,0,0) (0.01,0,0) (0,0.01,0) (ASCII PLY).
fs::path make_robot(const std::string& name, const std::string& finger_visuals) {
  const fs::path dir = fs::temp_directory_path() / ("plantar_test_vtk_links_" + name);
  fs::remove_all(dir);
  const float facets[4][3][3] = {{{0, 0, 0}, {0, 0.05f, 0}, {0.1f, 0, 0}},
                                 {{0, 0, 0}, {0.1f, 0, 0}, {0, 0, 0.02f}},
                                 {{0, 0, 0}, {0, 0, 0.02f}, {0, 0.05f, 0}},
                                 {{0.1f, 0, 0}, {0, 0.05f, 0}, {0, 0, 0.02f}}};
  std::string stl(80, ' '); // binary STL: header, count, (normal, 3 vertices, attribute) each
  stl.replace(0, 12, "binary wedge");
  const std::uint32_t n_facets = 4;
  stl.append(reinterpret_cast<const char*>(&n_facets), 4);
  for (const auto& facet : facets) {
    const float normal[3] = {0, 0, 0};
    const std::uint16_t attribute = 0;
    stl.append(reinterpret_cast<const char*>(normal), sizeof normal);
    stl.append(reinterpret_cast<const char*>(facet), sizeof facet);
    stl.append(reinterpret_cast<const char*>(&attribute), 2);
  }
  write_text(dir / "meshes/wedge.stl", stl);
  write_text(dir / "meshes/tri.ply", "ply\nformat ascii 1.0\nelement vertex 3\n"
                                     "property float x\nproperty float y\nproperty float z\n"
                                     "element face 1\nproperty list uchar int vertex_indices\n"
                                     "end_header\n0 0 0\n0.01 0 0\n0 0.01 0\n3 0 1 2\n");
  write_text(dir / "cube.obj",
             "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\n"
             "v 0 0 1\nv 1 0 1\nv 1 1 1\nv 0 1 1\n"
             "f 1 4 3 2\nf 5 6 7 8\nf 1 2 6 5\nf 2 3 7 6\nf 3 4 8 7\nf 4 1 5 8\n");
  write_text(dir / "robot.urdf", urdf_text(finger_visuals));
  return dir;
}

const std::string finger_meshes =
    mesh_visual("meshes/wedge.stl", "2 1 0.5", R"(xyz="0 0 0.05" rpy="0 0 1.5707963267948966")") +
    mesh_visual("file://" +
                    (fs::temp_directory_path() / "plantar_test_vtk_links_ok/cube.obj").string(),
                "0.02 0.04 0.06", R"(xyz="0 0 0.1")") +
    mesh_visual("meshes/tri.ply", "1 1 1", R"(xyz="0 0 0")");

/// True if every one of @p points is within tol of one of @p expected and each of @p expected
/// is matched.
bool same_point_set(const std::vector<Eigen::Vector3d>& points,
                    const std::vector<Eigen::Vector3d>& expected) {
  std::vector<bool> hit(expected.size(), false);
  for (const Eigen::Vector3d& x : points) {
    bool found = false;
    for (std::size_t k = 0; k < expected.size(); ++k)
      if ((x - expected[k]).norm() < tol)
        found = hit[k] = true;
    if (!found)
      return false;
  }
  for (bool h : hit)
    if (!h)
      return false;
  return true;
}

TEST(VtkLinks, ShapesAtTheirPoses) {
  const fs::path dir = make_robot("ok", finger_meshes);
  const fs::path urdf = dir / "robot.urdf";
  const auto model = multibody::build_model_from_urdf(urdf.string());
  const auto shapes = app::make_link_shapes(model, urdf, r_stick);
  const int base = model.body_id("base"), arm = model.body_id("arm"), hand = model.body_id("hand"),
            finger = model.body_id("finger");
  ASSERT_EQ(model.n_bodies, 5); // world, base (+ head), arm, hand (+ tip), finger

  // box, sphere, cylinder, STL, OBJ, PLY, stick to j3, stick to tip (in URDF order).
  using Kind = app::LinkShape::Kind;
  const std::vector<std::pair<Kind, std::string>> expected_shapes = {
      {Kind::box, "base"},    {Kind::sphere, "head"}, {Kind::cylinder, "arm"},
      {Kind::mesh, "finger"}, {Kind::mesh, "finger"}, {Kind::mesh, "finger"},
      {Kind::stick, "j3"},    {Kind::stick, "tip"}};
  ASSERT_EQ(shapes.size(), expected_shapes.size());
  std::map<std::string, const app::LinkShape*> shape_of;
  for (std::size_t s = 0; s < shapes.size(); ++s) {
    EXPECT_EQ(shapes[s].kind, expected_shapes[s].first) << s;
    EXPECT_EQ(shapes[s].source, expected_shapes[s].second) << s;
  }
  EXPECT_EQ(shapes[0].body, base);
  EXPECT_EQ(shapes[1].body, base);
  EXPECT_EQ(shapes[2].body, arm);
  EXPECT_EQ(shapes[3].body, finger);
  EXPECT_EQ(shapes[4].body, finger);
  EXPECT_EQ(shapes[5].body, finger);
  EXPECT_EQ(shapes[6].body, hand);
  EXPECT_EQ(shapes[7].body, hand);
  // Points after merging the sources' duplicates: box corners, cylinder rims (16 + 16),
  // sphere 16 meridians x 7 latitudes + 2 poles, the meshes' vertices.
  const std::vector<int> n_points = {8, 114, 32, 4, 8, 3, 32, 32};
  for (std::size_t s = 0; s < shapes.size(); ++s)
    EXPECT_EQ(shapes[s].points.cols(), n_points[s]) << s;

  // Base at (1, 2, 3), unrotated; j1 = pi/2 about y: arm, hand and finger have
  // R = R_y(pi/2), (x, y, z) -> (z, y, -x). Origins: arm (1, 2, 3.3), hand (1.5, 2, 3.3),
  // finger (1.7, 2, 3.3); tip frame (1.5, 2, 3.2).
  Eigen::VectorXd q = model.neutral_configuration();
  q.head<3>() << 1, 2, 3;
  q[model.idx_q[model.joint_id("j1")]] = M_PI / 2;
  multibody::Data data(model);
  multibody::forward_kinematics(model, data, q);
  const fs::path path = dir / "out/links_000000.vtp";
  app::write_links_vtp(model, data, shapes, path);

  // The file: VTK XML PolyData, binary, zlib; nothing else left in its directory.
  {
    std::ifstream in(path, std::ios::binary);
    std::string head(400, '\0');
    in.read(head.data(), static_cast<std::streamsize>(head.size()));
    EXPECT_NE(head.find("<VTKFile type=\"PolyData\""), std::string::npos) << head;
    EXPECT_NE(head.find("compressor=\"vtkZLibDataCompressor\""), std::string::npos) << head;
    std::stringstream rest;
    rest << in.rdbuf();
    EXPECT_NE(rest.str().find("<AppendedData encoding=\"raw\">"), std::string::npos);
    EXPECT_EQ(rest.str().find("format=\"ascii\""), std::string::npos);
  }
  int n_files = 0;
  for ([[maybe_unused]] const auto& entry : fs::directory_iterator(path.parent_path()))
    ++n_files;
  EXPECT_EQ(n_files, 1); // no temporary file left

  vtkNew<vtkXMLPolyDataReader> reader;
  reader->SetFileName(path.c_str());
  reader->Update();
  vtkPolyData* links = reader->GetOutput();
  ASSERT_NE(links, nullptr);
  vtkDataArray* body = links->GetCellData()->GetArray("body");
  ASSERT_NE(body, nullptr);
  EXPECT_EQ(std::string(links->GetPoints()->GetData()->GetDataTypeAsString()), "float");

  // One vertex per body at its origin: points 0..3, cells 0..3.
  ASSERT_EQ(links->GetNumberOfVerts(), 4);
  const std::map<int, Eigen::Vector3d> origins = {
      {base, {1, 2, 3}}, {arm, {1, 2, 3.3}}, {hand, {1.5, 2, 3.3}}, {finger, {1.7, 2, 3.3}}};
  for (vtkIdType c = 0; c < 4; ++c) {
    EXPECT_EQ(links->GetCellType(c), 1); // VTK_VERTEX
    const int b = static_cast<int>(body->GetTuple1(c));
    ASSERT_TRUE(origins.count(b)) << b;
    double x[3];
    links->GetPoint(links->GetCell(c)->GetPointId(0), x);
    EXPECT_LT((Eigen::Vector3d(x[0], x[1], x[2]) - origins.at(b)).norm(), tol) << "body " << b;
  }

  // The shapes' points follow the vertices in order; their polygons follow in order.
  vtkIdType point = 4, cell = 4;
  std::vector<std::vector<Eigen::Vector3d>> world(shapes.size());
  for (std::size_t s = 0; s < shapes.size(); ++s) {
    for (Eigen::Index k = 0; k < shapes[s].points.cols(); ++k, ++point) {
      double x[3];
      links->GetPoint(point, x);
      world[s].emplace_back(x[0], x[1], x[2]);
    }
    for (int k = 0; k < shapes[s].n_polygons(); ++k, ++cell) {
      EXPECT_EQ(static_cast<int>(body->GetTuple1(cell)), shapes[s].body) << s;
      vtkCell* polygon = links->GetCell(cell);
      ASSERT_GE(polygon->GetNumberOfPoints(), 3);
      for (vtkIdType i = 0; i < polygon->GetNumberOfPoints(); ++i) {
        const vtkIdType id = polygon->GetPointId(i);
        EXPECT_TRUE(id >= point - shapes[s].points.cols() && id < point) << "shape " << s;
      }
    }
  }
  EXPECT_EQ(point, links->GetNumberOfPoints());
  EXPECT_EQ(cell, links->GetNumberOfCells());

  auto bounds = [](const std::vector<Eigen::Vector3d>& x) {
    Eigen::Vector3d lo = x[0], hi = x[0];
    for (const auto& p : x) {
      lo = lo.cwiseMin(p);
      hi = hi.cwiseMax(p);
    }
    return std::make_pair(lo, hi);
  };
  auto expect_bounds = [&](std::size_t s, const Eigen::Vector3d& lo, const Eigen::Vector3d& hi) {
    const auto [a, b] = bounds(world[s]);
    EXPECT_LT((a - lo).norm(), tol) << "shape " << s << " lower bound " << a.transpose();
    EXPECT_LT((b - hi).norm(), tol) << "shape " << s << " upper bound " << b.transpose();
  };

  // Box 0.2 x 0.1 x 0.4 yawed 90 deg, centre (1, 2, 3.1): half extents (0.05, 0.1, 0.2).
  EXPECT_EQ(shapes[0].n_polygons(), 6);
  for (const auto& x : world[0]) {
    EXPECT_NEAR(std::abs(x.x() - 1), 0.05, tol);
    EXPECT_NEAR(std::abs(x.y() - 2), 0.1, tol);
    EXPECT_NEAR(std::abs(x.z() - 3.1), 0.2, tol);
  }
  expect_bounds(0, {0.95, 1.9, 2.9}, {1.05, 2.1, 3.3});
  // Sphere of radius 0.1 at base + (0, 0, 0.5) + (0.2, 0, 0) = (1.2, 2, 3.5).
  const Eigen::Vector3d centre(1.2, 2, 3.5);
  for (const auto& x : world[1])
    EXPECT_NEAR((x - centre).norm(), 0.1, tol);
  expect_bounds(1, centre.array() - 0.1, centre.array() + 0.1);
  // Cylinder r = 0.05, length 0.5, centre arm + R (0, 0, 0.25) = (1.25, 2, 3.3), axis world x.
  EXPECT_EQ(shapes[2].n_polygons(), 16 + 2); // sides and two caps
  for (const auto& x : world[2]) {
    EXPECT_NEAR(std::hypot(x.y() - 2, x.z() - 3.3), 0.05, tol);
    EXPECT_NEAR(std::abs(x.x() - 1.25), 0.25, tol);
  }
  expect_bounds(2, {1, 1.95, 3.25}, {1.5, 2.05, 3.35});
  // STL: v -> finger + R_y (Rz(90) diag(2, 1, 0.5) v + (0, 0, 0.05)): its 4 vertices
  // (0,0,0) (0.1,0,0) (0,0.05,0) (0,0,0.02) at:
  EXPECT_EQ(shapes[3].n_polygons(), 4);
  EXPECT_TRUE(same_point_set(world[3],
                             {{1.75, 2, 3.3}, {1.75, 2.2, 3.3}, {1.75, 2, 3.35}, {1.76, 2, 3.3}}));
  expect_bounds(3, {1.75, 2, 3.3}, {1.76, 2.2, 3.35});
  // OBJ: corner (a, b, c) -> finger + R_y (0.02 a, 0.04 b, 0.06 c + 0.1)
  //                       = (1.8 + 0.06 c, 2 + 0.04 b, 3.3 - 0.02 a).
  EXPECT_EQ(shapes[4].n_polygons(), 6);
  std::vector<Eigen::Vector3d> corners;
  for (int a = 0; a < 2; ++a)
    for (int b = 0; b < 2; ++b)
      for (int c = 0; c < 2; ++c)
        corners.emplace_back(1.8 + 0.06 * c, 2 + 0.04 * b, 3.3 - 0.02 * a);
  EXPECT_TRUE(same_point_set(world[4], corners));
  expect_bounds(4, {1.8, 2, 3.28}, {1.86, 2.04, 3.3});
  // PLY: v -> finger + R_y v, (x, y, z) -> (1.7 + z, 2 + y, 3.3 - x).
  EXPECT_EQ(shapes[5].n_polygons(), 1);
  EXPECT_TRUE(same_point_set(world[5], {{1.7, 2, 3.3}, {1.7, 2, 3.29}, {1.7, 2.01, 3.3}}));
  // Sticks of the hand: to j3 from (1.5, 2, 3.3) to (1.7, 2, 3.3), to the tip frame from
  // (1.5, 2, 3.3) to (1.5, 2, 3.2).
  for (const auto& x : world[6]) {
    EXPECT_NEAR(std::hypot(x.y() - 2, x.z() - 3.3), r_stick, tol);
    EXPECT_NEAR(std::abs(x.x() - 1.6), 0.1, tol);
  }
  for (const auto& x : world[7]) {
    EXPECT_NEAR(std::hypot(x.x() - 1.5, x.y() - 2), r_stick, tol);
    EXPECT_NEAR(std::abs(x.z() - 3.25), 0.05, tol);
  }
  expect_bounds(6, {1.5, 1.99, 3.29}, {1.7, 2.01, 3.31});
  expect_bounds(7, {1.49, 1.99, 3.2}, {1.51, 2.01, 3.3});
  fs::remove_all(dir);
}

/// The message of the std::runtime_error of make_link_shapes for finger visual @p visual.
std::string mesh_error(const std::string& name, const std::string& visual,
                       const std::function<void(const fs::path&)>& prepare = {}) {
  const fs::path dir = make_robot(name, visual);
  if (prepare)
    prepare(dir);
  const fs::path urdf = dir / "robot.urdf";
  const auto model = multibody::build_model_from_urdf(urdf.string());
  std::string message = "no exception";
  try {
    app::make_link_shapes(model, urdf, r_stick);
  } catch (const std::runtime_error& e) {
    message = e.what();
  }
  fs::remove_all(dir);
  std::printf("%s\n", message.c_str());
  return message;
}

void expect_contains(const std::string& text, const std::vector<std::string>& parts) {
  for (const std::string& part : parts)
    EXPECT_NE(text.find(part), std::string::npos) << "'" << part << "' not in: " << text;
}

TEST(VtkLinks, MeshErrorsNameTheFile) {
  const std::string origin = R"(xyz="0 0 0")";
  const std::string urdf = "robot.urdf", link = "link 'finger'";
  expect_contains(
      mesh_error("package", mesh_visual("package://robot/meshes/hand.stl", "1 1 1", origin)),
      {urdf, link, "package://robot/meshes/hand.stl", "ROS"});
  expect_contains(mesh_error("missing", mesh_visual("meshes/missing.stl", "1 1 1", origin)),
                  {urdf, link, "meshes/missing.stl", "no such file"});
  expect_contains(mesh_error("extension", mesh_visual("meshes/hand.dae", "1 1 1", origin),
                             [](const fs::path& dir) { write_text(dir / "meshes/hand.dae", "x"); }),
                  {urdf, link, "meshes/hand.dae", "unsupported extension '.dae'"});
  expect_contains(mesh_error("empty", mesh_visual("meshes/empty.stl", "1 1 1", origin),
                             [](const fs::path& dir) { write_text(dir / "meshes/empty.stl", ""); }),
                  {urdf, link, "meshes/empty.stl"});
}

TEST(VtkLinks, RejectsBadInput) {
  const fs::path dir = make_robot("bad", "");
  const fs::path urdf = dir / "robot.urdf";
  const auto model = multibody::build_model_from_urdf(urdf.string());
  try {
    app::make_link_shapes(model, urdf, 0.0);
    FAIL() << "no exception";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("Output/VTK stick radius = 0"), std::string::npos);
  }
  try {
    app::make_link_shapes(model, dir / "nowhere.urdf", r_stick);
    FAIL() << "no exception";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("nowhere.urdf"), std::string::npos) << e.what();
  }
  fs::remove_all(dir);
}

} // namespace
