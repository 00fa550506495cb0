// The reduced sole (coupling/reduced_sole.h) against the full condensed sole of
// meshes/sole_box.geo (P1 tetrahedra, 3 cm, the humanoid scenes' sole):
//  * C_r = A^T C A equals the product with an explicit dense aggregation matrix A (1e-14);
//  * with one node per patch (identity patches, and a grid fine enough) C_r equals C to
//    round-off (1e-14 relative);
//  * on nested grids 1x1, 2x2, 4x4, ... the rigid-motion stiffness K_r = R_r^T C_r^-1 R_r
//    stays below the full K = R^T C^-1 R in the Loewner order and approaches it
//    monotonically (complementary energy: patch-wise constant forces are a subspace), so the
//    scaled error ||D^-1/2 (K - K_r) D^-1/2||_2, D = diag(K), decreases to round-off.

#include "condensation_test_utilities.h"
#include "coupling/reduced_sole.h"
#include "fem/material_table.h"

#include <Eigen/Cholesky>
#include <Eigen/Eigenvalues>
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdio>
#include <vector>

namespace plantar::coupling {
namespace {

CondensedSole make_sole() {
  dealii::Triangulation<3> tria;
  const auto groups = testing::load_sole_mesh(tria, {{"SoleMeshSize", 0.03}, {"SoleHex", 0}});
  const fem::MaterialTable materials(fem::LinearElasticMaterial(4e6, 0.3, "rubber"));
  CondensationParameters parameters;
  parameters.attached_boundary = groups.surface("top");
  parameters.contact_boundary = groups.surface("bottom");
  return CondensedSole(tria, materials, parameters);
}

/// Dense A (3n x 3P), A_kj = I / n_j for node k in patch j.
Eigen::MatrixXd aggregation_matrix(const std::vector<int>& patch_of_node, int n_patches) {
  const int n = static_cast<int>(patch_of_node.size());
  std::vector<int> size(n_patches, 0);
  for (int j : patch_of_node)
    ++size[j];
  Eigen::MatrixXd a = Eigen::MatrixXd::Zero(3 * n, 3 * n_patches);
  for (int k = 0; k < n; ++k)
    a.block<3, 3>(3 * k, 3 * patch_of_node[k]) =
        Eigen::Matrix3d::Identity() / size[patch_of_node[k]];
  return a;
}

TEST(ReducedSole, MatchesDenseAggregationAndFullModel) {
  const CondensedSole sole = make_sole();
  const int n = sole.n_contacts();
  ASSERT_GE(n, 8);
  const Eigen::MatrixXd& c = sole.compliance();
  for (const int g : {1, 2, 3, 5}) {
    const auto patches = ReducedSole::grid_patches(sole.contact_positions(), g, g);
    const ReducedSole reduced(sole.contact_positions(), c, patches);
    const Eigen::MatrixXd a = aggregation_matrix(patches, reduced.n_patches());
    const Eigen::MatrixXd dense = a.transpose() * c * a;
    EXPECT_LT((reduced.compliance() - dense).cwiseAbs().maxCoeff(),
              1e-14 * dense.cwiseAbs().maxCoeff())
        << g << "x" << g;
    int total = 0;
    for (int s : reduced.patch_sizes())
      total += s;
    EXPECT_EQ(total, n);
    EXPECT_EQ(Eigen::LLT<Eigen::MatrixXd>(reduced.compliance()).info(), Eigen::Success);
  }
  // One node per patch: C_r = C (same order).
  std::vector<int> identity(n);
  for (int k = 0; k < n; ++k)
    identity[k] = k;
  const ReducedSole full(sole.contact_positions(), c, identity);
  const double error = (full.compliance() - c).cwiseAbs().maxCoeff() / c.cwiseAbs().maxCoeff();
  std::printf("one node per patch: max |C_r - C| / max |C| = %.2e (%d nodes)\n", error, n);
  EXPECT_LT(error, 1e-14);
  EXPECT_LT((full.patch_positions() - sole.contact_positions()).cwiseAbs().maxCoeff(), 1e-15);
}

TEST(ReducedSole, RigidStiffnessConvergesMonotonically) {
  const CondensedSole sole = make_sole();
  const int n = sole.n_contacts();
  const Eigen::Vector3d origin = sole.contact_positions().colwise().mean().transpose();
  const Eigen::Matrix<double, 6, 6> k_full =
      rigid_motion_stiffness(sole.contact_positions(), sole.compliance(), origin);
  const Eigen::Matrix<double, 6, 1> scale = k_full.diagonal().cwiseSqrt().cwiseInverse();
  std::printf("full: %d nodes, K diag = %.4g %.4g %.4g N/m, %.4g %.4g %.4g N m/rad\n", n,
              k_full(0, 0), k_full(1, 1), k_full(2, 2), k_full(3, 3), k_full(4, 4), k_full(5, 5));
  double previous_error = 2.0;
  Eigen::Matrix<double, 6, 6> k_previous = Eigen::Matrix<double, 6, 6>::Zero();
  int levels = 0, max_patch = n;
  for (int g = 1; max_patch > 1 && g <= 1024; g *= 2, ++levels) {
    const auto patches = ReducedSole::grid_patches(sole.contact_positions(), g, g);
    const ReducedSole reduced(sole.contact_positions(), sole.compliance(), patches);
    max_patch = *std::max_element(reduced.patch_sizes().begin(), reduced.patch_sizes().end());
    // K_r by the same formula at the patch centres; its pseudo-rank is 3 for one patch.
    Eigen::Matrix<double, 6, 6> k_r;
    if (reduced.n_patches() >= 3) {
      k_r = rigid_motion_stiffness(reduced.patch_positions(), reduced.compliance(), origin);
    } else {
      Eigen::MatrixXd r = Eigen::MatrixXd::Zero(3 * reduced.n_patches(), 6);
      for (int j = 0; j < reduced.n_patches(); ++j) {
        const Eigen::Vector3d d = reduced.patch_positions().row(j).transpose() - origin;
        r.block<3, 3>(3 * j, 0).setIdentity();
        r.block<3, 3>(3 * j, 3) << 0, d.z(), -d.y(), -d.z(), 0, d.x(), d.y(), -d.x(), 0;
      }
      k_r = r.transpose() * reduced.compliance().ldlt().solve(r);
    }
    const Eigen::Matrix<double, 6, 6> gap =
        scale.asDiagonal() * (k_full - k_r) * scale.asDiagonal();
    const Eigen::Matrix<double, 6, 6> step =
        scale.asDiagonal() * (k_r - k_previous) * scale.asDiagonal();
    const Eigen::SelfAdjointEigenSolver<Eigen::Matrix<double, 6, 6>> eig_gap(
        0.5 * (gap + gap.transpose()));
    const Eigen::SelfAdjointEigenSolver<Eigen::Matrix<double, 6, 6>> eig_step(
        0.5 * (step + step.transpose()));
    const double error = eig_gap.eigenvalues().cwiseAbs().maxCoeff();
    // The library's estimate (Sole/Reduced patches = auto) is this scaled error.
    EXPECT_NEAR(reduction_error_estimate(k_full, reduced, origin), error, 1e-9 * (1 + error)) << g;
    std::printf("grid %4dx%-4d patches %4d (max %3d nodes): ||D^-1/2 (K - K_r) D^-1/2||_2 = "
                "%.3e, K_r,zz / K_zz = %.6f, K_r,xx(rot) / K_xx(rot) = %.6f\n",
                g, g, reduced.n_patches(), max_patch, error, k_r(2, 2) / k_full(2, 2),
                k_r(3, 3) / k_full(3, 3));
    // Loewner order: K_r <= K, and K_r grows under refinement.
    EXPECT_GT(eig_gap.eigenvalues().minCoeff(), -1e-10) << g;
    EXPECT_GT(eig_step.eigenvalues().minCoeff(), -1e-10) << g;
    EXPECT_LE(error, previous_error * (1 + 1e-12)) << g;
    previous_error = error;
    k_previous = k_r;
  }
  EXPECT_EQ(max_patch, 1) << "no grid up to 1024x1024 separates the nodes";
  EXPECT_GE(levels, 4);
  EXPECT_LT(previous_error, 1e-10) << "one node per patch must reproduce the full model";
}

// Sole/Reduced patches = auto: the coarsest grid meeting the tolerance. On the 3 cm sole
// (63 nodes) the estimates are 1.02 (1x1), 0.28 (2x2), 0.12 (4x4), 0.026 (8x8, 55 patches);
// 16x16 has one node per patch (no reduction), so a tolerance below 0.026 leaves the full sole
// (reached = false).
TEST(ReducedSole, ChoiceMeetsTheToleranceAtTheLeastCost) {
  const CondensedSole sole = make_sole();
  const Eigen::MatrixX3d& x = sole.contact_positions();
  const Eigen::Vector3d origin = x.colwise().mean().transpose();
  const Eigen::Matrix<double, 6, 6> k_full = rigid_motion_stiffness(x, sole.compliance(), origin);
  const auto estimate = [&](int g) {
    return reduction_error_estimate(
        k_full, ReducedSole(x, sole.compliance(), ReducedSole::grid_patches(x, g, g)), origin);
  };
  for (const double tolerance : {2.0, 0.5, 0.2, 0.05, 0.01}) {
    const ReductionChoice choice = choose_reduction(x, sole.compliance(), tolerance);
    std::printf("tolerance %.2f: grid %d, %d contacts, estimate %.3f, reached %d\n", tolerance,
                choice.grid, choice.n_patches, choice.estimate, choice.reached);
    if (choice.reached) {
      ASSERT_GE(choice.grid, 1);
      EXPECT_LE(choice.estimate, tolerance);
      EXPECT_NEAR(choice.estimate, estimate(choice.grid), 1e-12);
      EXPECT_LT(choice.n_patches, sole.n_contacts());
      if (choice.grid > 1)
        EXPECT_GT(estimate(choice.grid / 2), tolerance) << "a coarser grid meets it";
    } else {
      EXPECT_EQ(choice.grid, 0);
      EXPECT_EQ(choice.n_patches, sole.n_contacts());
      EXPECT_GT(estimate(8), tolerance);
      const auto patches = ReducedSole::grid_patches(x, 16, 16);
      EXPECT_EQ(*std::max_element(patches.begin(), patches.end()) + 1, sole.n_contacts());
    }
  }
  EXPECT_EQ(choose_reduction(x, sole.compliance(), 2.0).grid, 1);
  EXPECT_EQ(choose_reduction(x, sole.compliance(), 0.5).grid, 2);
  EXPECT_EQ(choose_reduction(x, sole.compliance(), 0.2).grid, 4);
  EXPECT_EQ(choose_reduction(x, sole.compliance(), 0.05).grid, 8);
  EXPECT_FALSE(choose_reduction(x, sole.compliance(), 0.01).reached);
  EXPECT_THROW(choose_reduction(x, sole.compliance(), 0.0), std::invalid_argument);
}

TEST(ReducedSole, RejectsBadInput) {
  Eigen::MatrixX3d x = Eigen::MatrixX3d::Random(4, 3);
  const Eigen::MatrixXd c = Eigen::MatrixXd::Identity(12, 12);
  EXPECT_THROW(ReducedSole(x, c, {0, 1, 2}), std::invalid_argument);
  EXPECT_THROW(ReducedSole(x, c, {0, 2, 2, 0}), std::invalid_argument); // patch 1 empty
  EXPECT_THROW(ReducedSole(x, Eigen::MatrixXd::Identity(9, 9), {0, 0, 0, 0}),
               std::invalid_argument);
  EXPECT_THROW(ReducedSole::grid_patches(x, 0, 2), std::invalid_argument);
  const ReducedSole one(x, c, {0, 0, 0, 0});
  EXPECT_NEAR(one.compliance()(0, 0), 0.25, 1e-15); // (1/4)^2 * 4 diagonal entries
}

} // namespace
} // namespace plantar::coupling
