// Sole/Reduced patches = auto (issue 25): the humanoid scene builds the reduced sole whose
// reduction error estimate meets Sole/Reduction tolerance, reports the grid and the estimate
// in its summary, and falls back to the full sole (reached = false) when no grid does. The
// numbers against coupling::choose_reduction on the same condensed sole's dense C (the scene
// builds its reduced sole from the factorization of K, without C), and against the grid sizes
// of coupling::ReducedSole::grid_shares in the scene's basis (bilinear by default: one contact
// per grid vertex).
#include "apps/condensed_sole_foot.h"
#include "apps/humanoid_simulation.h"
#include "apps/scene.h"
#include "coupling/condensed_sole.h"
#include "coupling/reduced_sole.h"
#include "humanoid_test_utilities.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cstdio>
#include <stdexcept>
#include <string>

namespace plantar::app {
namespace {

Scene auto_scene(const std::string& tolerance) {
  return testing::load_humanoid_scene("stand", {{"Robot/Foot form", "fem sole"},
                                                {"Sole/Reduced patches", "auto"},
                                                {"Sole/Reduction tolerance", tolerance},
                                                {"Simulation/Duration", "0.01"}});
}

TEST(ReducedSoleChoice, SceneBuildsTheChosenGridAndReportsItsEstimate) {
  // The full sole of the same scene, for the expected choice.
  Scene full = auto_scene("0.2");
  full.sole_reduction = {};
  HumanoidSimulation reference(full);
  const int n = reference.summary().n_sole_nodes;
  const auto& sole_foot = dynamic_cast<const CondensedSoleFoot&>(reference.foot_model());
  const coupling::CondensedSole& sole = *sole_foot.sole();
  for (const char* tolerance : {"0.5", "0.2", "0.05", "0.01", "0.0001"}) {
    // The scene's default shares a patch's force by node area (coupling::pressure_weights),
    // in the bilinear basis.
    const Scene scene = auto_scene(tolerance);
    ASSERT_TRUE(scene.sole_reduction.area_weights);
    ASSERT_EQ(scene.sole_reduction.basis, coupling::PatchBasis::bilinear);
    Eigen::VectorXd load(3 * n), areas(n);
    sole.contact_load(Eigen::Vector3d(0, 0, 1), load);
    for (int k = 0; k < n; ++k)
      areas[k] = load[3 * k + 2];
    const coupling::ReductionChoice expected =
        coupling::choose_reduction(sole.contact_positions(), sole.compliance(),
                                   std::stod(tolerance), scene.sole_reduction.spacing,
                                   coupling::pressure_weights(areas), scene.sole_reduction.basis);
    HumanoidSimulation simulation(scene);
    simulation.run();
    const HumanoidSummary& s = simulation.summary();
    std::printf("tolerance %s: grid %d x %d, %d contacts per foot (full %d), estimate %.4f, "
                "reached %d\n",
                tolerance, s.sole_reduction_x, s.sole_reduction_y, s.n_sole_nodes, n,
                s.sole_reduction_estimate, s.sole_reduction_reached);
    EXPECT_EQ(s.sole_reduction_x, expected.grid);
    EXPECT_EQ(s.sole_reduction_y, expected.grid);
    EXPECT_EQ(s.sole_reduction_reached, expected.reached);
    // The scene's reduced sole is built from the factorization of K, the expected one from C.
    EXPECT_NEAR(s.sole_reduction_estimate, expected.estimate, 1e-12 * expected.estimate);
    if (expected.reached) {
      const coupling::ReducedSole::ShareMatrix shares = coupling::ReducedSole::grid_shares(
          sole.contact_positions(), expected.grid, expected.grid, scene.sole_reduction.spacing,
          scene.sole_reduction.basis, coupling::pressure_weights(areas));
      EXPECT_EQ(s.n_sole_nodes, shares.cols());
      EXPECT_EQ(s.n_sole_nodes, (expected.grid + 1) * (expected.grid + 1));
      EXPECT_LE(s.sole_reduction_estimate, std::stod(tolerance));
      EXPECT_GT(s.sole_reduction_estimate, 0.0);
    } else {
      EXPECT_EQ(s.n_sole_nodes, n);
      EXPECT_EQ(s.sole_reduction_estimate, 0.0);
    }
    EXPECT_NEAR(s.simulated_time, 0.01, 1e-9);
  }
}

TEST(ReducedSoleChoice, GivenGridReportsItsEstimate) {
  Scene scene = auto_scene("0.2");
  scene.sole_reduction.automatic = false;
  scene.sole_reduction.patches_x = scene.sole_reduction.patches_y = 2;
  scene.sole_reduction.basis = coupling::PatchBasis::constant;
  HumanoidSimulation simulation(scene);
  // The 3 cm sole's 2 x 2 estimate with area shares in the constant basis (test reduced_sole:
  // 0.3113).
  EXPECT_NEAR(simulation.summary().sole_reduction_estimate, 0.3113, 0.001);
  EXPECT_EQ(simulation.summary().sole_reduction_x, 2);
}

// Sole/Reduction basis = bilinear: one contact per grid vertex ((g + 1)^2 on this sole), the
// estimate of the scene's sole (from the factorization of K) equal to the dense route's, the
// auto choice equal to choose_reduction's in that basis, and the robot standing on it: the
// contact force balances its weight.
TEST(ReducedSoleChoice, BilinearBasisScene) {
  Scene full = auto_scene("0.2");
  full.sole_reduction = {};
  HumanoidSimulation reference(full);
  const int n = reference.summary().n_sole_nodes;
  const coupling::CondensedSole& sole =
      *dynamic_cast<const CondensedSoleFoot&>(reference.foot_model()).sole();
  Eigen::VectorXd load(3 * n), areas(n);
  sole.contact_load(Eigen::Vector3d(0, 0, 1), load);
  for (int k = 0; k < n; ++k)
    areas[k] = load[3 * k + 2];
  const Eigen::VectorXd weights = coupling::pressure_weights(areas);
  const Eigen::MatrixX3d& x = sole.contact_positions();
  const Eigen::Vector3d origin = x.colwise().mean().transpose();
  Scene scene = testing::load_humanoid_scene("stand", {{"Robot/Foot form", "fem sole"},
                                                       {"Sole/Reduced patches", "4, 4"},
                                                       {"Sole/Reduction basis", "bilinear"},
                                                       {"Simulation/Duration", "0.3"}});
  ASSERT_EQ(scene.sole_reduction.basis, coupling::PatchBasis::bilinear);
  HumanoidSimulation simulation(scene);
  simulation.run();
  const HumanoidSummary& s = simulation.summary();
  const coupling::ReducedSole dense(
      x, sole.compliance(),
      coupling::ReducedSole::grid_shares(x, 4, 4, scene.sole_reduction.spacing,
                                         coupling::PatchBasis::bilinear, weights));
  const double expected =
      coupling::reduction_error_estimate(sole.rigid_motion_stiffness(), dense, origin);
  const double weight = s.robot_mass * 9.81;
  std::printf("bilinear 4 x 4: %d contacts per foot (full %d), estimate %.4f; force %.2f N for "
              "a weight of %.2f N\n",
              s.n_sole_nodes, n, s.sole_reduction_estimate, s.final_contact_force.z(), weight);
  EXPECT_EQ(s.n_sole_nodes, 25);
  EXPECT_NEAR(s.sole_reduction_estimate, expected, 1e-10 * expected);
  EXPECT_NEAR(s.final_contact_force.z(), weight, 5e-3 * weight);
  EXPECT_NEAR(s.simulated_time, 0.3, 1e-9);
  // auto in the bilinear basis.
  Scene automatic = auto_scene("0.02");
  automatic.sole_reduction.basis = coupling::PatchBasis::bilinear;
  const coupling::ReductionChoice choice =
      coupling::choose_reduction(x, sole.compliance(), 0.02, automatic.sole_reduction.spacing,
                                 weights, coupling::PatchBasis::bilinear);
  HumanoidSimulation chosen(automatic);
  EXPECT_TRUE(choice.reached);
  EXPECT_EQ(chosen.summary().sole_reduction_x, choice.grid);
  EXPECT_EQ(chosen.summary().n_sole_nodes, choice.n_patches);
  EXPECT_NEAR(chosen.summary().sole_reduction_estimate, choice.estimate, 1e-10 * choice.estimate);
}

/// The feet's nodal normal contact forces (N, per node of the full sole) at the end of
/// @p simulation's run: a reduced sole's patch forces shared by its nodes (S F).
std::array<Eigen::VectorXd, 2> nodal_normal_forces(const HumanoidSimulation& simulation) {
  const auto& foot = dynamic_cast<const CondensedSoleFoot&>(simulation.foot_model());
  std::array<Eigen::VectorXd, 2> forces;
  for (int side = 0; side < 2; ++side) {
    const Eigen::VectorXd& f = foot.pad(side).force(); // (n, t1, t2) per contact
    const Eigen::VectorXd normal =
        Eigen::Map<const Eigen::VectorXd, 0, Eigen::InnerStride<3>>(f.data(), f.size() / 3);
    forces[side] = foot.reduced() ? Eigen::VectorXd(foot.reduced()->shares() * normal) : normal;
  }
  return forces;
}

// Sole/Reduction quantity = pressure: auto picks the coarsest grid whose pressure estimate meets
// the tolerance, the summary reports both estimates, and the estimate predicts the field: the
// robot standing still (both soles flat on the ground, nearly a bonded face in a rigid motion)
// has, after 0.3 s, a relative L2 error of the nodal normal force field against the full sole
// within the estimate (plus the stiffness estimate: the two models carry the same weight at
// slightly different approaches and tilts).
TEST(ReducedSoleChoice, PressureToleranceBoundsTheStandingField) {
  const auto stand = [](const std::vector<std::pair<std::string, std::string>>& entries) {
    std::vector<std::pair<std::string, std::string>> all{{"Robot/Foot form", "fem sole"},
                                                         {"Simulation/Duration", "0.3"}};
    all.insert(all.end(), entries.begin(), entries.end());
    return testing::load_humanoid_scene("stand", all);
  };
  HumanoidSimulation full(stand({}));
  full.run();
  const auto reference = nodal_normal_forces(full);
  const coupling::CondensedSole& sole =
      *dynamic_cast<const CondensedSoleFoot&>(full.foot_model()).sole();
  const int n = sole.n_contacts();
  Eigen::VectorXd load(3 * n), areas(n);
  sole.contact_load(Eigen::Vector3d(0, 0, 1), load);
  for (int k = 0; k < n; ++k)
    areas[k] = load[3 * k + 2];
  const Eigen::VectorXd weights = coupling::pressure_weights(areas);
  int last_grid = 0;
  for (const char* tolerance : {"0.3", "0.15", "0.08"}) {
    const Scene scene = stand({{"Sole/Reduced patches", "auto"},
                               {"Sole/Reduction quantity", "pressure"},
                               {"Sole/Reduction tolerance", tolerance}});
    ASSERT_EQ(scene.sole_reduction.quantity, coupling::ReductionQuantity::pressure);
    const coupling::ReductionChoice expected = coupling::choose_reduction(
        sole.contact_positions(), sole.compliance(), std::stod(tolerance),
        scene.sole_reduction.spacing, weights, scene.sole_reduction.basis,
        coupling::ReductionQuantity::pressure);
    ASSERT_TRUE(expected.reached) << tolerance;
    HumanoidSimulation reduced(scene);
    reduced.run();
    const HumanoidSummary& s = reduced.summary();
    EXPECT_EQ(s.sole_reduction_x, expected.grid);
    EXPECT_NEAR(s.sole_reduction_pressure_estimate, expected.pressure_estimate,
                1e-10 * expected.pressure_estimate);
    EXPECT_NEAR(s.sole_reduction_estimate, expected.estimate, 1e-10 * expected.estimate);
    EXPECT_LE(s.sole_reduction_pressure_estimate, std::stod(tolerance));
    EXPECT_GE(s.sole_reduction_x, last_grid);
    last_grid = s.sole_reduction_x;
    const auto forces = nodal_normal_forces(reduced);
    for (int side = 0; side < 2; ++side) {
      const double error = (forces[side] - reference[side]).norm() / reference[side].norm();
      std::printf("pressure tolerance %s: grid %d x %d (%d contacts per foot), pressure "
                  "estimate %.4f, stiffness estimate %.4f; standing foot %d: field error %.4f "
                  "(%.0f N)\n",
                  tolerance, s.sole_reduction_x, s.sole_reduction_y, s.n_sole_nodes,
                  s.sole_reduction_pressure_estimate, s.sole_reduction_estimate, side, error,
                  reference[side].sum());
      EXPECT_LE(error, s.sole_reduction_pressure_estimate + s.sole_reduction_estimate);
    }
  }
}

TEST(ReducedSoleChoice, BadEntriesAreNamed) {
  for (const auto& [entry, value] : std::vector<std::pair<std::string, std::string>>{
           {"Sole/Reduction tolerance", "0"}, {"Sole/Reduced patches", "automatic"}}) {
    try {
      testing::load_humanoid_scene("stand", {{entry, value}});
      ADD_FAILURE() << entry << " = " << value << " was accepted";
    } catch (const std::exception& e) {
      const std::string what = e.what();
      EXPECT_NE(what.find(entry.substr(5)), std::string::npos) << what;
      EXPECT_NE(what.find(value), std::string::npos) << what;
    }
  }
}

} // namespace
} // namespace plantar::app
