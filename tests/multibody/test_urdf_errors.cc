// Every URDF error of the loader gives a message naming the file and the element.
#include "multibody/urdf_loader.h"
#include "tests/multibody/test_helpers.h"

#include <gtest/gtest.h>

#include <cstdio>
#include <functional>
#include <string>

namespace plantar::multibody {
namespace {

/// Runs @p load, expects an exception of type E whose message contains every fragment.
template <typename E>
void expect_error(const std::function<void()>& load, const std::vector<std::string>& fragments) {
  try {
    load();
    ADD_FAILURE() << "no exception thrown";
  } catch (const E& error) {
    const std::string message = error.what();
    std::printf("message: %s\n", message.c_str());
    for (const auto& fragment : fragments) {
      EXPECT_NE(message.find(fragment), std::string::npos)
          << "message '" << message << "' lacks '" << fragment << "'";
    }
  }
}

const char* kLink = R"(<link name="%s"><inertial><mass value="1"/>
  <inertia ixx="0.01" ixy="0" ixz="0" iyy="0.01" iyz="0" izz="0.01"/></inertial></link>)";

std::string link(const std::string& name) {
  char buffer[512];
  std::snprintf(buffer, sizeof buffer, kLink, name.c_str());
  return buffer;
}

std::string joint(const std::string& name, const std::string& type, const std::string& parent,
                  const std::string& child) {
  return "<joint name=\"" + name + "\" type=\"" + type + "\"><parent link=\"" + parent +
         "\"/><child link=\"" + child +
         "\"/><axis xyz=\"0 0 1\"/><limit lower=\"-1\" upper=\"1\" effort=\"10\" "
         "velocity=\"1\"/></joint>";
}

std::string robot(const std::string& body) {
  return "<robot name=\"r\">" + body + "</robot>";
}

TEST(UrdfErrors, MissingFile) {
  const std::string path = test::model_path("test/does_not_exist.urdf");
  expect_error<std::runtime_error>([&] { build_model_from_urdf(path); },
                                   {path, "cannot be opened"});
}

TEST(UrdfErrors, UnknownJointType) {
  const std::string xml = robot(link("a") + link("b") + joint("j_ball", "ball", "a", "b"));
  expect_error<std::runtime_error>([&] { build_model_from_urdf_string(xml, {}, "ball.urdf"); },
                                   {"ball.urdf", "j_ball", "ball"});
}

TEST(UrdfErrors, UnsupportedPlanarJoint) {
  const std::string xml = robot(link("a") + link("b") + joint("j_planar", "planar", "a", "b"));
  expect_error<std::runtime_error>([&] { build_model_from_urdf_string(xml, {}, "planar.urdf"); },
                                   {"planar.urdf", "j_planar", "planar", "supported types"});
}

TEST(UrdfErrors, MovingLinkWithoutInertia) {
  // "b" is moved by j1 and has neither an inertial nor massive descendants ("c" is massless too).
  const std::string xml = robot(link("a") + "<link name=\"b\"/><link name=\"c\"/>" +
                                joint("j1", "revolute", "a", "b") + joint("j2", "fixed", "b", "c"));
  expect_error<std::runtime_error>(
      [&] {
        ModelOptions options;
        options.floating_base = false;
        build_model_from_urdf_string(xml, options, "massless.urdf");
      },
      {"massless.urdf", "link 'b'", "joint 'j1'", "inertia"});
}

TEST(UrdfErrors, KinematicLoopLinkWithTwoParents) {
  const std::string xml =
      robot(link("a") + link("b") + link("c") + joint("j1", "revolute", "a", "b") +
            joint("j2", "revolute", "a", "c") + joint("j3", "revolute", "b", "c"));
  expect_error<std::runtime_error>([&] { build_model_from_urdf_string(xml, {}, "loop.urdf"); },
                                   {"loop.urdf", "link 'c'", "j2", "j3", "kinematic loop"});
}

TEST(UrdfErrors, ClosedCycleWithoutRoot) {
  // a -> b -> a: every link has a parent, so there is no root.
  const std::string xml = robot(link("a") + link("b") + joint("j1", "revolute", "a", "b") +
                                joint("j2", "revolute", "b", "a"));
  expect_error<std::runtime_error>([&] { build_model_from_urdf_string(xml, {}, "cycle.urdf"); },
                                   {"cycle.urdf", "root"});
}

TEST(UrdfErrors, JointWithUnknownChildLink) {
  const std::string xml = robot(link("a") + joint("j1", "revolute", "a", "ghost"));
  expect_error<std::runtime_error>([&] { build_model_from_urdf_string(xml, {}, "ghost.urdf"); },
                                   {"ghost.urdf", "ghost"});
}

TEST(UrdfErrors, CompliantAnkleOnUnknownFootAndBadStiffness) {
  const std::string path = test::model_path("test/spring_foot.urdf");
  ModelOptions options;
  options.floating_base = false;
  options.compliant_ankle.foot_links = {"no_such_foot"};
  expect_error<std::invalid_argument>([&] { build_model_from_urdf(path, options); },
                                      {"no_such_foot", "spring_foot.urdf"});
  options.compliant_ankle.foot_links = {"foot"};
  options.compliant_ankle.linear_stiffness = -5.0;
  expect_error<std::invalid_argument>([&] { build_model_from_urdf(path, options); },
                                      {"stiffness", "-5"});
}

} // namespace
} // namespace plantar::multibody
