// Every input check of fem/ triggered, and its message checked: the
// parameter, its value and the allowed range (or the file and group).
#include "fem/discretization.h"
#include "fem/linear_solver.h"
#include "fem/material_table.h"

#include <gtest/gtest.h>

#include <functional>

namespace plantar::fem {
namespace {

std::string error_of(const std::function<void()>& f) {
  try {
    f();
  } catch (const std::exception& e) {
    return e.what();
  }
  return "";
}

void expect_message(const std::function<void()>& f, const std::vector<std::string>& parts) {
  const std::string message = error_of(f);
  std::printf("message: %s\n", message.c_str());
  ASSERT_FALSE(message.empty()) << "no exception thrown";
  for (const auto& part : parts)
    EXPECT_NE(message.find(part), std::string::npos) << "'" << part << "' missing in: " << message;
}

TEST(BadInput, YoungsModulus) {
  expect_message([] { LinearElasticMaterial(0.0, 0.3, "rubber"); },
                 {"Young's modulus", "rubber", "= 0", "E must be > 0"});
  expect_message([] { LinearElasticMaterial(-4e6, 0.3); }, {"-4e+06", "> 0"});
}

TEST(BadInput, PoissonRatio) {
  expect_message([] { LinearElasticMaterial(4e6, 0.5, "heel"); },
                 {"Poisson ratio", "heel", "0.5", "-1 < nu < 0.5"});
  expect_message([] { LinearElasticMaterial(4e6, -1.0); }, {"-1", "-1 < nu < 0.5"});
}

TEST(BadInput, ElementDegree) {
  expect_message([] { Discretization(CellKind::tetrahedron, 3); },
                 {"degree", "3", "allowed 1 or 2"});
}

TEST(BadInput, LinearSolverKind) {
  expect_message([] { LinearSolverSettings::parse_kind("cholesky"); },
                 {"cholesky", "direct, iterative"});
}

TEST(BadInput, MaterialStrings) {
  expect_message([] { parse_material_specs("rubber E=4e6", "Materials"); },
                 {"Materials", "rubber E=4e6"});
  expect_message([] { parse_material_specs("rubber: E=4MPa", "Materials"); },
                 {"Materials", "4MPa", "not a number"});
  expect_message([] { parse_material_specs("", "Materials"); }, {"Materials", "no material"});
  expect_message([] { parse_material_specs("a: E=1; a: E=2", "Materials"); }, {"repeated", "a"});
}

TEST(BadInput, MaterialRegionsAgainstMesh) {
  PhysicalGroups groups;
  groups.file = "sole.msh";
  groups.volumes = {{"rubber", 4}, {"heel", 5}};
  groups.n_cells = {{4, 10}, {5, 3}};
  expect_message(
      [&] { MaterialTable(parse_material_specs("rubber: E=4e6, nu=0.3", "Materials"), groups); },
      {"heel", "sole.msh", "no material"});
  expect_message(
      [&] {
        MaterialTable(parse_material_specs("rubber: E=4e6, nu=0.3; heel: E=1e6, nu=0.3; toe: E=1, "
                                           "nu=0.1",
                                           "Materials"),
                      groups);
      },
      {"toe", "sole.msh"});
  expect_message(
      [&] {
        MaterialTable(parse_material_specs("rubber: E=4e6, nu=0.3; heel: E=1e6, nu=0.7", "M"),
                      groups);
      },
      {"heel", "0.7", "-1 < nu < 0.5"});
  expect_message(
      [&] {
        MaterialTable(parse_material_specs("rubber: E=4e6; heel: E=1e6, nu=0.3", "M"), groups);
      },
      {"rubber", "missing parameter 'nu'"});
  expect_message(
      [&] {
        MaterialTable(parse_material_specs("rubber: E=4e6, nu=0.3, G=1; heel: E=1e6, nu=0.3", "M"),
                      groups);
      },
      {"rubber", "unknown parameter 'G'", "E, nu"});
}

} // namespace
} // namespace plantar::fem
