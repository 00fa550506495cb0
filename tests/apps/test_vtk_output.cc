// The links of the ParaView series (apps/scene_vtk_links.h): URDF <visual> box and cylinder,
// a stick for a link without geometry, written at a known configuration and read back from
// the VTU; every point is compared with the hand-computed pose (the VTU read by VTK itself
// is tests/apps/test_vtk_output.py).

#include "apps/scene_vtk_links.h"

#include "multibody/kinematics.h"
#include "multibody/urdf_loader.h"

#include <urdf_parser/urdf_parser.h>

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>
#include <string>
#include <vector>

namespace {

using namespace plantar;

const char* const urdf_text = R"(<?xml version="1.0"?>
<robot name="vtk_links">
  <link name="base">
    <inertial><mass value="1"/><inertia ixx="1" ixy="0" ixz="0" iyy="1" iyz="0" izz="1"/></inertial>
    <visual><origin xyz="0 0 0.1" rpy="0 0 1.5707963267948966"/>
      <geometry><box size="0.2 0.1 0.4"/></geometry></visual>
  </link>
  <joint name="j1" type="revolute"><parent link="base"/><child link="arm"/>
    <origin xyz="0 0 0.3"/><axis xyz="0 1 0"/>
    <limit lower="-3" upper="3" effort="10" velocity="1"/></joint>
  <link name="arm">
    <inertial><mass value="1"/><inertia ixx="1" ixy="0" ixz="0" iyy="1" iyz="0" izz="1"/></inertial>
    <collision><origin xyz="0 0 0.25"/>
      <geometry><cylinder radius="0.05" length="0.5"/></geometry></collision>
  </link>
  <joint name="j2" type="revolute"><parent link="arm"/><child link="hand"/>
    <origin xyz="0 0 0.5"/><axis xyz="0 1 0"/>
    <limit lower="-3" upper="3" effort="10" velocity="1"/></joint>
  <link name="hand">
    <inertial><mass value="1"/><inertia ixx="1" ixy="0" ixz="0" iyy="1" iyz="0" izz="1"/></inertial>
  </link>
  <joint name="tip_joint" type="fixed"><parent link="hand"/><child link="tip"/>
    <origin xyz="0.1 0 0"/></joint>
  <link name="tip"/>
</robot>)";

struct Vtu {
  std::vector<Eigen::Vector3d> points;
  std::vector<std::vector<int>> cells;
  std::vector<int> types, bodies;
};

/// The values of the first ASCII DataArray whose tag contains @p marker.
std::vector<double> array_of(const std::string& text, const std::string& marker) {
  const auto start = text.find('>', text.find(marker)) + 1;
  std::istringstream in(text.substr(start, text.find("</DataArray>", start) - start));
  std::vector<double> values;
  for (double v; in >> v;)
    values.push_back(v);
  return values;
}

Vtu read_vtu(const std::filesystem::path& path) {
  std::ifstream in(path);
  std::stringstream buffer;
  buffer << in.rdbuf();
  const std::string text = buffer.str();
  Vtu vtu;
  const auto xyz = array_of(text, "NumberOfComponents=\"3\""); // the Points array
  for (std::size_t i = 0; i + 2 < xyz.size(); i += 3)
    vtu.points.emplace_back(xyz[i], xyz[i + 1], xyz[i + 2]);
  const auto connectivity = array_of(text, "Name=\"connectivity\"");
  const auto offsets = array_of(text, "Name=\"offsets\"");
  for (double t : array_of(text, "Name=\"types\""))
    vtu.types.push_back(static_cast<int>(t));
  for (double b : array_of(text, "Name=\"body\""))
    vtu.bodies.push_back(static_cast<int>(b));
  int begin = 0;
  for (double end : offsets) {
    vtu.cells.emplace_back(connectivity.begin() + begin, connectivity.begin() + int(end));
    begin = static_cast<int>(end);
  }
  return vtu;
}

TEST(VtkLinks, ShapesAtTheirPoses) {
  const auto model = multibody::build_model_from_urdf_string(urdf_text, {}, "vtk_links");
  const auto urdf = urdf::parseURDF(urdf_text);
  ASSERT_TRUE(urdf);
  const double radius = 0.01;
  const auto shapes = app::make_link_shapes(model, *urdf, radius);
  ASSERT_EQ(shapes.size(), 3u); // box (base), cylinder (arm, collision), stick hand -> tip

  // Base at (1, 2, 3), unrotated; j1 = pi/2 about y turns the arm's z axis onto world x.
  Eigen::VectorXd q = model.neutral_configuration();
  q.head<3>() << 1, 2, 3;
  q[model.idx_q[model.joint_id("j1")]] = M_PI / 2;
  multibody::Data data(model);
  multibody::forward_kinematics(model, data, q);
  const auto path = std::filesystem::temp_directory_path() / "plantar_test_vtk_links.vtu";
  app::write_links_vtu(model, data, shapes, path);
  const Vtu vtu = read_vtu(path);
  std::filesystem::remove(path);
  ASSERT_EQ(vtu.types.size(), vtu.cells.size());
  ASSERT_EQ(vtu.bodies.size(), vtu.cells.size());

  const int base = model.body_id("base"), arm = model.body_id("arm"), hand = model.body_id("hand");
  std::map<int, int> count; // VTK cell type -> cells
  for (std::size_t c = 0; c < vtu.cells.size(); ++c) {
    ++count[vtu.types[c]];
    for (int id : vtu.cells[c]) {
      const Eigen::Vector3d& x = vtu.points.at(id);
      if (vtu.types[c] == 1) { // body origins
        const Eigen::Vector3d expected = vtu.bodies[c] == base  ? Eigen::Vector3d(1, 2, 3)
                                         : vtu.bodies[c] == arm ? Eigen::Vector3d(1, 2, 3.3)
                                                                : Eigen::Vector3d(1.5, 2, 3.3);
        EXPECT_LT((x - expected).norm(), 1e-9) << "body " << vtu.bodies[c];
      } else if (vtu.types[c] == 12) { // the box, rotated 90 deg about z: 0.1 x 0.2 x 0.4
        EXPECT_EQ(vtu.bodies[c], base);
        EXPECT_NEAR(std::abs(x.x() - 1), 0.05, 1e-9);
        EXPECT_NEAR(std::abs(x.y() - 2), 0.1, 1e-9);
        EXPECT_NEAR(std::abs(x.z() - 3.1), 0.2, 1e-9);
      } else if (vtu.bodies[c] == arm) { // cylinder along world x from x = 1 to 1.5
        EXPECT_NEAR(std::hypot(x.y() - 2, x.z() - 3.3), 0.05, 1e-9);
        EXPECT_NEAR(std::abs(x.x() - 1.25), 0.25, 1e-9);
      } else { // stick of the hand: tip frame at hand + R (0.1, 0, 0), R = R_y(pi/2)
        EXPECT_EQ(vtu.bodies[c], hand);
        EXPECT_NEAR(std::hypot(x.x() - 1.5, x.y() - 2), radius, 1e-9);
        EXPECT_NEAR(std::abs(x.z() - 3.25), 0.05, 1e-9);
      }
    }
  }
  EXPECT_EQ(count[1], 3);      // one vertex per body
  EXPECT_EQ(count[12], 1);     // the box
  EXPECT_EQ(count[9], 2 * 16); // two cylinders of 16 sides
  EXPECT_EQ(count[7], 2 * 2);  // their caps
}

TEST(VtkLinks, RejectsBadStickRadius) {
  const auto model = multibody::build_model_from_urdf_string(urdf_text, {}, "vtk_links");
  const auto urdf = urdf::parseURDF(urdf_text);
  try {
    app::make_link_shapes(model, *urdf, 0.0);
    FAIL() << "no exception";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("Output/VTK stick radius = 0"), std::string::npos);
  }
}

} // namespace
