// The reduced sole (coupling/reduced_sole.h) against the full condensed sole of
// meshes/sole_box.geo (P1 tetrahedra, 3 cm, the humanoid scenes' sole):
//  * C_r = A^T C A equals the product with an explicit dense aggregation matrix A (1e-14);
//  * with one node per patch (identity patches, and a grid fine enough) C_r equals C to
//    round-off (1e-14 relative);
//  * on nested grids 1x1, 2x2, 4x4, ... the rigid-motion stiffness K_r = R_r^T C_r^-1 R_r
//    stays below the full K = R^T C^-1 R in the Loewner order and approaches it
//    monotonically (complementary energy: patch-wise constant forces are a subspace), so the
//    scaled error ||D^-1/2 (K - K_r) D^-1/2||_2, D = diag(K), decreases to round-off;
//  * the factorization form (no dense C) gives the same C_r, rigid stiffness, choice and
//    fields as the dense one;
//  * the field recovered from a reduced sole's patch forces (u = K^-1 B A F) differs from the
//    full sole's under the same rigid motion a of the contact face by exactly the stiffness
//    gap: ||u - u_r||_K^2 = a^T (K_R - K_r) a (Galerkin orthogonality of the complementary
//    energy), so its relative energy error in a coordinate direction is at most the square
//    root of the reduction error estimate;
//  * the bilinear basis (one patch per grid vertex) represents a linear pressure exactly and
//    reaches a smaller estimate than the constant basis with fewer patches;
//  * the pressure estimate is the worst relative error of the bonded face's normal nodal
//    forces over its approaches, pitches and rolls: no sampled motion exceeds it, the worst of
//    20,000 motions reaches it, both forms agree (P1 and P2), and auto on the pressure meets
//    its tolerance at the coarsest grid.

#include "condensation_test_utilities.h"
#include "coupling/reduced_sole.h"
#include "fem/material_table.h"

#include <Eigen/Cholesky>
#include <Eigen/Eigenvalues>
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <vector>

namespace plantar::coupling {
namespace {

CondensedSole make_sole(CondensationParameters::Form form = CondensationParameters::Form::dense,
                        unsigned int degree = 1, bool hexahedra = false) {
  dealii::Triangulation<3> tria;
  const auto groups =
      testing::load_sole_mesh(tria, {{"SoleMeshSize", 0.03}, {"SoleHex", hexahedra ? 1.0 : 0.0}});
  const fem::MaterialTable materials(fem::LinearElasticMaterial(4e6, 0.3, "rubber"));
  CondensationParameters parameters;
  parameters.attached_boundary = groups.surface("top");
  parameters.contact_boundary = groups.surface("bottom");
  parameters.form = form;
  parameters.degree = degree;
  parameters.block_size = 7; // several blocks, the last one partial
  return CondensedSole(tria, materials, parameters);
}

/// Consistent areas a_k = int N_k ds of the contact nodes (m^2).
Eigen::VectorXd node_areas(const CondensedSole& sole) {
  Eigen::VectorXd load(3 * sole.n_contacts()), areas(sole.n_contacts());
  sole.contact_load(Eigen::Vector3d(0, 0, 1), load);
  for (int k = 0; k < sole.n_contacts(); ++k)
    areas[k] = load[3 * k + 2];
  return areas;
}

double relative_difference(const Eigen::MatrixXd& a, const Eigen::MatrixXd& b) {
  return (a - b).cwiseAbs().maxCoeff() / b.cwiseAbs().maxCoeff();
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
// 16x16 has one node per patch (no reduction). Between the nested grids the choice is
// bisected: the grid one coarser than the choice misses the tolerance, every grid from 1 to 8
// checked by its own estimate. A tolerance below the estimate of every grid with fewer patches
// than nodes (g up to 32) leaves the full sole (reached = false).
TEST(ReducedSole, ChoiceMeetsTheToleranceAtTheLeastCost) {
  const CondensedSole sole = make_sole();
  const Eigen::MatrixX3d& x = sole.contact_positions();
  const Eigen::Vector3d origin = x.colwise().mean().transpose();
  const Eigen::Matrix<double, 6, 6> k_full = rigid_motion_stiffness(x, sole.compliance(), origin);
  const auto estimate = [&](int g) {
    return reduction_error_estimate(
        k_full, ReducedSole(x, sole.compliance(), ReducedSole::grid_patches(x, g, g)), origin);
  };
  const auto n_patches = [&](int g) {
    const auto patches = ReducedSole::grid_patches(x, g, g);
    return *std::max_element(patches.begin(), patches.end()) + 1;
  };
  double least = 1e300; // the least estimate of a grid with fewer patches than nodes
  for (int g = 1; g <= 32; ++g)
    if (n_patches(g) < sole.n_contacts())
      least = std::min(least, estimate(g));
  ASSERT_GT(least, 0.0);
  for (const double tolerance : {2.0, 0.5, 0.2, 0.05, 0.01, 0.5 * least}) {
    const ReductionChoice choice = choose_reduction(x, sole.compliance(), tolerance);
    std::printf("tolerance %.3g: grid %d, %d contacts, estimate %.3g, reached %d\n", tolerance,
                choice.grid, choice.n_patches, choice.estimate, choice.reached);
    if (choice.reached) {
      ASSERT_GE(choice.grid, 1);
      EXPECT_LE(choice.estimate, tolerance);
      EXPECT_NEAR(choice.estimate, estimate(choice.grid), 1e-12);
      EXPECT_LT(choice.n_patches, sole.n_contacts());
      if (choice.grid > 1) {
        EXPECT_GT(estimate(choice.grid - 1), tolerance) << "a coarser grid meets it";
      }
    } else {
      EXPECT_EQ(choice.grid, 0);
      EXPECT_EQ(choice.n_patches, sole.n_contacts());
      for (int g = 1; g <= 32; ++g)
        if (n_patches(g) < sole.n_contacts()) {
          EXPECT_GT(estimate(g), tolerance) << "grid " << g << " meets it";
        }
      EXPECT_EQ(n_patches(16), sole.n_contacts());
    }
  }
  // The estimates of grids 1 to 8, and for tolerances between them, the coarsest grid meeting
  // each (the estimate falls with g on this sole, asserted here).
  std::vector<double> estimates;
  for (int g = 1; g <= 8; ++g) {
    estimates.push_back(estimate(g));
    std::printf("grid %d: estimate %.4f\n", g, estimates.back());
    if (g > 1) {
      EXPECT_LT(estimates[g - 1], estimates[g - 2]);
    }
  }
  for (int g = 1; g <= 8; ++g) {
    const double tolerance = 1.01 * estimates[g - 1];
    EXPECT_EQ(choose_reduction(x, sole.compliance(), tolerance).grid, g) << tolerance;
  }
  EXPECT_EQ(choose_reduction(x, sole.compliance(), 2.0).grid, 1);
  EXPECT_EQ(choose_reduction(x, sole.compliance(), 0.5).grid, 2);
  EXPECT_FALSE(choose_reduction(x, sole.compliance(), 0.5 * least).reached);
  EXPECT_THROW(choose_reduction(x, sole.compliance(), 0.0), std::invalid_argument);
}

TEST(ReducedSole, FactorizationFormEqualsDenseForm) {
  using Form = CondensationParameters::Form;
  for (const unsigned int degree : {1u, 2u}) {
    const CondensedSole dense = make_sole(Form::dense, degree);
    const CondensedSole factored = make_sole(Form::factorization, degree);
    const Eigen::MatrixX3d& x = dense.contact_positions();
    const Eigen::MatrixXd& c = dense.compliance();
    const int n = dense.n_contacts();
    EXPECT_EQ(factored.compliance().size(), 0);
    EXPECT_GT(factored.memory().recovery_factorization_bytes, 0u);
    EXPECT_EQ(factored.memory().compliance_bytes, 0u);
    // K_R through K_nn (both forms) against R^T C^-1 R from the dense C.
    const Eigen::Vector3d origin = x.colwise().mean().transpose();
    const Eigen::Matrix<double, 6, 6> k_dense = rigid_motion_stiffness(x, c, origin);
    const double e_rigid = relative_difference(dense.rigid_motion_stiffness(), k_dense);
    const double e_rigid_f = relative_difference(factored.rigid_motion_stiffness(), k_dense);
    // C_r by 3P solves against A^T C A, and the identity patches' C_r = C.
    double e_reduced = 0;
    std::vector<int> identity(n);
    for (int k = 0; k < n; ++k)
      identity[k] = k;
    std::vector<std::vector<int>> assignments{identity};
    for (const int g : {1, 2, 3, 5})
      assignments.push_back(ReducedSole::grid_patches(x, g, g));
    for (const auto& patches : assignments) {
      const ReducedSole from_c(x, c, patches), from_k(factored, patches);
      e_reduced =
          std::max(e_reduced, relative_difference(from_k.compliance(), from_c.compliance()));
      EXPECT_LT((from_k.patch_positions() - from_c.patch_positions()).cwiseAbs().maxCoeff(), 1e-15);
    }
    // Fields of the same contact forces.
    const Eigen::VectorXd f = Eigen::VectorXd::Random(3 * n);
    dealii::Vector<double> u_dense, u_factored;
    dense.displacement_of_forces(f, u_dense);
    factored.displacement_of_forces(f, u_factored);
    u_factored -= u_dense;
    const double e_field = u_factored.linfty_norm() / u_dense.linfty_norm();
    const Eigen::VectorXd u_c = c * f;
    double e_contact = 0;
    for (int k = 0; k < n; ++k)
      for (int d = 0; d < 3; ++d)
        e_contact =
            std::max(e_contact, std::abs(u_dense(dense.contact_dofs()[k][d]) - u_c(3 * k + d)));
    e_contact /= u_c.cwiseAbs().maxCoeff();
    std::printf("P%u, %d nodes: K_R dense %.1e, factorization %.1e; C_r %.1e; field %.1e; "
                "contact rows of the field vs C f %.1e; factor kept %.2f MB against C %.2f MB\n",
                degree, n, e_rigid, e_rigid_f, e_reduced, e_field, e_contact,
                factored.memory().recovery_factorization_bytes / 1e6,
                dense.memory().compliance_bytes / 1e6);
    EXPECT_LT(e_rigid, 1e-9);
    EXPECT_LT(e_rigid_f, 1e-9);
    EXPECT_LT(e_reduced, 1e-11);
    EXPECT_LT(e_field, 1e-11);
    EXPECT_LT(e_contact, 1e-12);
    // The same choice of grid from either form.
    for (const double tolerance : {0.5, 0.2, 0.05, 0.01}) {
      const ReductionChoice a = choose_reduction(x, c, tolerance);
      const ReductionChoice b = choose_reduction(factored, tolerance);
      EXPECT_EQ(a.grid, b.grid) << tolerance;
      EXPECT_EQ(a.reached, b.reached) << tolerance;
      EXPECT_NEAR(a.estimate, b.estimate, 1e-9) << tolerance;
    }
    dealii::Vector<double> field;
    EXPECT_THROW(factored.recover(Eigen::VectorXd::Zero(3 * n), field), std::logic_error);
    EXPECT_THROW(factored.displacement_of_forces(Eigen::VectorXd::Zero(3), field),
                 std::invalid_argument);
    EXPECT_THROW(factored.projected_compliance(ReducedSole::aggregation({0, 0, 1})),
                 std::invalid_argument);
  }
  // Released factorization: C_r kept by the caller, the sole answers no more solves.
  CondensedSole released = make_sole(CondensationParameters::Form::factorization);
  const std::size_t kept = released.memory().total();
  EXPECT_TRUE(released.has_solver());
  released.release_factorization();
  EXPECT_FALSE(released.has_solver());
  EXPECT_LT(released.memory().total(), kept);
  dealii::Vector<double> field;
  EXPECT_THROW(
      released.displacement_of_forces(Eigen::VectorXd::Zero(3 * released.n_contacts()), field),
      std::logic_error);
  EXPECT_THROW(ReducedSole(released, ReducedSole::grid_patches(released.contact_positions(), 2, 2)),
               std::logic_error);
  CondensationParameters bad;
  bad.form = CondensationParameters::Form::factorization;
  bad.compute_stiffness = true;
  EXPECT_THROW(bad.validate(), std::invalid_argument);
}

// coupling::rigid_motion_map: column i < 3 moves every point by e_i, column 3 + i by the rotation
// e_i x (x_k - x_0).
TEST(ReducedSole, RigidMotionMapIsTranslationsThenRotations) {
  Eigen::MatrixX3d x(3, 3);
  x << 0.1, -0.2, 0.03, -0.05, 0.07, 0.0, 0.2, 0.1, -0.01;
  const Eigen::Vector3d origin(0.01, 0.02, -0.03);
  const Eigen::MatrixXd r = rigid_motion_map(x, origin);
  ASSERT_EQ(r.rows(), 9);
  ASSERT_EQ(r.cols(), 6);
  for (Eigen::Index k = 0; k < x.rows(); ++k)
    for (int i = 0; i < 3; ++i) {
      const Eigen::Vector3d e = Eigen::Vector3d::Unit(i);
      EXPECT_LT((r.block<3, 1>(3 * k, i) - e).norm(), 1e-15);
      const Eigen::Vector3d rotated = e.cross(Eigen::Vector3d(x.row(k).transpose() - origin));
      EXPECT_LT((r.block<3, 1>(3 * k, 3 + i) - rotated).norm(), 1e-15);
    }
}

TEST(ReducedSole, RecoveredFieldErrorIsTheStiffnessGap) {
  const CondensedSole full = make_sole();
  const CondensedSole factored = make_sole(CondensationParameters::Form::factorization);
  const Eigen::MatrixX3d& x = full.contact_positions();
  const Eigen::Vector3d origin = x.colwise().mean().transpose();
  const Eigen::MatrixXd r = rigid_motion_map(x, origin);
  const Eigen::Matrix<double, 6, 6>& k_full = full.rigid_motion_stiffness();
  const dealii::SparseMatrix<double>& k = full.elasticity().stiffness_matrix();
  double worst_identity = 0, worst_ratio = 0;
  // Equal shares, shares by node area and the bilinear basis (any shares: the identity is
  // Galerkin's).
  const Eigen::VectorXd areas = pressure_weights(node_areas(full));
  for (const int basis : {0, 1, 2})
    for (const int g : {2, 4, 8}) {
      const auto shares = ReducedSole::grid_shares(
          x, g, g, GridSpacing::uniform, basis == 2 ? PatchBasis::bilinear : PatchBasis::constant,
          basis == 0 ? Eigen::VectorXd() : areas);
      const ReducedSole reduced(factored, shares);
      const Eigen::SparseMatrix<double, Eigen::ColMajor, int> a = ReducedSole::aggregation(shares);
      const Eigen::MatrixXd r_r = rigid_motion_map(reduced.patch_positions(), origin);
      const Eigen::LDLT<Eigen::MatrixXd> c_r(reduced.compliance());
      const Eigen::Matrix<double, 6, 6> k_r = r_r.transpose() * c_r.solve(r_r);
      const double estimate = reduction_error_estimate(k_full, reduced, origin);
      for (int i = 0; i < 6; ++i) {
        // Full: the contact face moved rigidly by a = e_i. Reduced: the patch forces that move
        // the patch means by the same motion, shared by the nodes.
        dealii::Vector<double> u_full, u_reduced, difference, ku(k.m());
        full.recover(r.col(i), u_full);
        factored.displacement_of_forces(a * c_r.solve(r_r.col(i)), u_reduced);
        // Its patch means are the prescribed motion: A^T u_c = R_r a.
        Eigen::VectorXd u_c(3 * x.rows());
        for (Eigen::Index n = 0; n < x.rows(); ++n)
          for (int d = 0; d < 3; ++d)
            u_c(3 * n + d) = u_reduced(full.contact_dofs()[n][d]);
        EXPECT_LT((a.transpose() * u_c - r_r.col(i)).cwiseAbs().maxCoeff(),
                  1e-10 * r_r.col(i).cwiseAbs().maxCoeff())
            << g << " " << i;
        difference = u_full;
        difference -= u_reduced;
        const double error2 = k.matrix_norm_square(difference);
        const double energy2 = k.matrix_norm_square(u_full);
        const double gap = k_full(i, i) - k_r(i, i);
        worst_identity = std::max(worst_identity, std::abs(error2 - gap) / k_full(i, i));
        const double relative = std::sqrt(error2 / energy2);
        worst_ratio = std::max(worst_ratio, relative / std::sqrt(estimate));
        EXPECT_NEAR(energy2, k_full(i, i), 1e-9 * k_full(i, i)) << g << " " << i;
        EXPECT_NEAR(error2, gap, 1e-8 * k_full(i, i)) << g << " " << i;
        EXPECT_LE(relative, std::sqrt(estimate) * (1 + 1e-9)) << g << " " << i;
        if (i == 2 || i == 3)
          std::printf("grid %dx%d, motion %d: relative energy error of the field %.4f, "
                      "sqrt(estimate) %.4f\n",
                      g, g, i, relative, std::sqrt(estimate));
      }
    }
  std::printf("max |(||u - u_r||_K^2 - (K_R - K_r)_ii)| / K_R,ii = %.1e; max relative energy "
              "error / sqrt(estimate) = %.3f\n",
              worst_identity, worst_ratio);
}

// Chebyshev-graded grids (cells at the Chebyshev-Lobatto points, small at the edges): nested
// under doubling, so their estimate falls monotonically too; printed against the uniform grids'.
TEST(ReducedSole, ChebyshevGridsAreNestedAndConverge) {
  const CondensedSole sole = make_sole();
  const Eigen::MatrixX3d& x = sole.contact_positions();
  const Eigen::Vector3d origin = x.colwise().mean().transpose();
  const int n = sole.n_contacts();
  double previous = 2;
  std::vector<int> coarse;
  for (int g = 1; g <= 16; g *= 2) {
    const auto patches = ReducedSole::grid_patches(x, g, g, GridSpacing::chebyshev);
    const ReducedSole reduced(x, sole.compliance(), patches);
    const double estimate =
        reduction_error_estimate(sole.rigid_motion_stiffness(), reduced, origin);
    const ReducedSole uniform(x, sole.compliance(), ReducedSole::grid_patches(x, g, g));
    std::printf("grid %2dx%-2d chebyshev: %2d patches, estimate %.4f; uniform: %2d patches, "
                "estimate %.4f\n",
                g, g, reduced.n_patches(), estimate, uniform.n_patches(),
                reduction_error_estimate(sole.rigid_motion_stiffness(), uniform, origin));
    EXPECT_LE(estimate, previous * (1 + 1e-12)) << g;
    if (!coarse.empty()) { // every fine patch lies in one coarse patch
      std::vector<int> parent(reduced.n_patches(), -1);
      for (int k = 0; k < n; ++k) {
        int& p = parent[patches[k]];
        if (p < 0)
          p = coarse[k];
        EXPECT_EQ(p, coarse[k]) << "grid " << g << ", node " << k;
      }
    }
    // Cells of the graded grid: the two edge columns (rows) are narrower than the middle ones.
    if (g == 8) {
      const double lo = x.col(0).minCoeff(), hi = x.col(0).maxCoeff();
      const double edge = (1 - std::cos(M_PI / 8)) / 2 * (hi - lo);
      for (int k = 0; k < n; ++k) {
        if (x(k, 0) >= lo + 0.99 * edge)
          continue;
        for (int l = 0; l < n; ++l) {
          if (patches[l] == patches[k]) {
            EXPECT_LT(x(l, 0), lo + edge * (1 + 1e-9)) << k << " " << l;
          }
        }
      }
    }
    previous = estimate;
    coarse = patches;
  }
}

// Shares by node area (a uniform patch pressure): A_kj = (a_k / A_j) I, C_r = A^T C A against
// the explicit product, nested grids monotone; on the P2 sole, whose vertex nodes carry no
// area, a far smaller estimate than equal shares.
TEST(ReducedSole, AreaSharesGiveAUniformPatchPressure) {
  for (const unsigned int degree : {1u, 2u}) {
    const CondensedSole sole = make_sole(CondensationParameters::Form::dense, degree);
    const Eigen::MatrixX3d& x = sole.contact_positions();
    const Eigen::Vector3d origin = x.colwise().mean().transpose();
    const Eigen::VectorXd areas = node_areas(sole);
    const Eigen::VectorXd weights = pressure_weights(areas);
    EXPECT_NEAR(areas.sum(), 0.2172 * 0.138, 1e-9); // the sole's bottom face
    double previous = 2;
    for (int g = 1; g <= 8; g *= 2) {
      const auto patches = ReducedSole::grid_patches(x, g, g, GridSpacing::chebyshev);
      const ReducedSole area(sole, patches, weights), equal(sole, patches);
      const Eigen::MatrixXd a = Eigen::MatrixXd(ReducedSole::aggregation(patches, weights));
      EXPECT_LT(relative_difference(area.compliance(), a.transpose() * sole.compliance() * a),
                1e-13);
      Eigen::VectorXd total = Eigen::VectorXd::Zero(area.n_patches());
      for (int k = 0; k < sole.n_contacts(); ++k) {
        total[patches[k]] += area.shares().coeff(k, patches[k]);
        // A uniform pressure: every node's share is its area over its patch's (above the floor).
        if (areas[k] > 1e-3 * areas.mean()) {
          double patch_area = 0;
          for (int l = 0; l < sole.n_contacts(); ++l)
            if (patches[l] == patches[k])
              patch_area += weights[l];
          EXPECT_NEAR(area.shares().coeff(k, patches[k]), areas[k] / patch_area, 1e-12);
        }
      }
      EXPECT_LT((total.array() - 1).abs().maxCoeff(), 1e-12);
      const double e_area = reduction_error_estimate(sole.rigid_motion_stiffness(), area, origin);
      const double e_equal = reduction_error_estimate(sole.rigid_motion_stiffness(), equal, origin);
      std::printf("P%u, %d nodes, graded %dx%d: estimate %.4f with area shares, %.4f equal\n",
                  degree, sole.n_contacts(), g, g, e_area, e_equal);
      EXPECT_LE(e_area, previous * (1 + 1e-12)) << g;
      previous = e_area;
      if (degree == 2 && g >= 4) {
        EXPECT_LT(e_area, 0.5 * e_equal) << g;
      }
    }
  }
  EXPECT_THROW(pressure_weights(Eigen::VectorXd::Zero(3)), std::invalid_argument);
  EXPECT_EQ(pressure_weights(Eigen::Vector3d(2, 0, 1))[1], 1e-3);
  EXPECT_THROW(ReducedSole::aggregation({0, 0}, Eigen::Vector2d(1, 0)), std::invalid_argument);
}

// The bilinear basis (one patch per grid vertex, S_kv = phi_v(x_k) w_k / W_v): nonnegative
// shares summing to 1 per vertex, at most 4 vertices per node; C_r from the factorization of K
// equal to the explicit dense A^T C A; a linear pressure field represented exactly (its nodal
// forces a_k (alpha + beta x + gamma y) lie in the range of S: the least-squares residual is
// round-off, and not for the constant basis); nested graded grids monotone; with the nodes at
// the vertices of a uniform grid, C_r is C renumbered (estimate 0); and fewer patches than the
// constant basis for a smaller estimate.
TEST(ReducedSole, BilinearBasisRepresentsContinuousPressures) {
  const CondensedSole dense = make_sole(CondensationParameters::Form::dense);
  const CondensedSole factored = make_sole(CondensationParameters::Form::factorization);
  const Eigen::MatrixX3d& x = dense.contact_positions();
  const int n = dense.n_contacts();
  const Eigen::Vector3d origin = x.colwise().mean().transpose();
  const Eigen::VectorXd areas = node_areas(dense);
  const Eigen::VectorXd weights = pressure_weights(areas);
  Eigen::VectorXd linear(n); // nodal forces of the pressure 1e4 (1 + 5 x - 3 y) Pa
  for (int k = 0; k < n; ++k)
    linear[k] = areas[k] * 1e4 * (1 + 5 * x(k, 0) - 3 * x(k, 1));
  const auto residual = [&](const ReducedSole::ShareMatrix& shares) {
    const Eigen::MatrixXd s(shares);
    const Eigen::VectorXd fit = s * s.colPivHouseholderQr().solve(linear);
    return (fit - linear).norm() / linear.norm();
  };
  double previous = 2;
  for (int g = 1; g <= 4; g *= 2) {
    const auto shares =
        ReducedSole::grid_shares(x, g, g, GridSpacing::chebyshev, PatchBasis::bilinear, weights);
    ASSERT_EQ(shares.rows(), n);
    EXPECT_EQ(shares.cols(), (g + 1) * (g + 1)); // every vertex covers a node on this mesh
    const Eigen::MatrixXd s(shares);
    EXPECT_GE(s.minCoeff(), 0.0);
    EXPECT_LT((s.colwise().sum().array() - 1).abs().maxCoeff(), 1e-13);
    for (int k = 0; k < n; ++k)
      EXPECT_LE((s.row(k).array() > 0).count(), 4);
    const ReducedSole from_k(factored, shares);
    const Eigen::MatrixXd a = Eigen::MatrixXd(ReducedSole::aggregation(shares));
    EXPECT_LT(relative_difference(from_k.compliance(), a.transpose() * dense.compliance() * a),
              1e-12);
    const double e_linear = residual(shares);
    const double e_constant = residual(ReducedSole::partition_shares(
        ReducedSole::grid_patches(x, g, g, GridSpacing::chebyshev), weights));
    const double estimate =
        reduction_error_estimate(dense.rigid_motion_stiffness(), from_k, origin);
    std::printf("bilinear graded %dx%d: %d patches, estimate %.4g, linear pressure residual "
                "%.2e (constant basis %.2e)\n",
                g, g, from_k.n_patches(), estimate, e_linear, e_constant);
    EXPECT_LT(e_linear, 1e-12) << g;
    EXPECT_GT(e_constant, 1e-3) << g;
    EXPECT_LE(estimate, previous * (1 + 1e-12)) << g;
    previous = estimate;
  }
  // The Q1 hexahedra's bottom nodes lie on a uniform (nx + 1) x (ny + 1) lattice: the vertices'
  // hats are the nodes.
  const CondensedSole hex = make_sole(CondensationParameters::Form::dense, 1, true);
  const Eigen::MatrixX3d& xh = hex.contact_positions();
  const int nh = hex.n_contacts();
  std::vector<double> xs, ys;
  for (int k = 0; k < nh; ++k) {
    xs.push_back(std::round(xh(k, 0) * 1e9));
    ys.push_back(std::round(xh(k, 1) * 1e9));
  }
  std::sort(xs.begin(), xs.end());
  std::sort(ys.begin(), ys.end());
  const int nx = int(std::unique(xs.begin(), xs.end()) - xs.begin()) - 1;
  const int ny = int(std::unique(ys.begin(), ys.end()) - ys.begin()) - 1;
  ASSERT_EQ((nx + 1) * (ny + 1), nh);
  const auto lattice = ReducedSole::grid_shares(xh, nx, ny, GridSpacing::uniform,
                                                PatchBasis::bilinear, node_areas(hex));
  const ReducedSole exact(xh, hex.compliance(), lattice);
  EXPECT_EQ(exact.n_patches(), nh);
  EXPECT_LT(reduction_error_estimate(hex.rigid_motion_stiffness(), exact,
                                     xh.colwise().mean().transpose()),
            1e-12);
  const Eigen::MatrixXd a = Eigen::MatrixXd(ReducedSole::aggregation(lattice));
  EXPECT_EQ((a.array() != 0).count(), 3 * nh); // a permutation
  // Fewer contacts for a smaller estimate than the constant basis.
  const auto estimate_of = [&](int g, PatchBasis basis) {
    const ReducedSole r(factored,
                        ReducedSole::grid_shares(x, g, g, GridSpacing::chebyshev, basis, weights));
    return std::make_pair(r.n_patches(),
                          reduction_error_estimate(dense.rigid_motion_stiffness(), r, origin));
  };
  const auto [p_bilinear, e_bilinear] = estimate_of(4, PatchBasis::bilinear);
  const auto [p_constant, e_constant] = estimate_of(8, PatchBasis::constant);
  std::printf("bilinear 4x4: %d patches, estimate %.4g; constant 8x8: %d patches, %.4g\n",
              p_bilinear, e_bilinear, p_constant, e_constant);
  EXPECT_LT(p_bilinear, p_constant);
  EXPECT_LT(e_bilinear, e_constant);
  EXPECT_THROW(
      ReducedSole::grid_shares(x, 0, 2, GridSpacing::uniform, PatchBasis::bilinear, weights),
      std::invalid_argument);
  EXPECT_THROW(ReducedSole::grid_shares(x, 2, 2, GridSpacing::uniform, PatchBasis::bilinear,
                                        Eigen::VectorXd::Zero(n)),
               std::invalid_argument);
}

// The pressure estimate against a direct evaluation with dense matrices: f = K_c R a by the
// stiffness of the compliance (LLT of C, inverted), f_r = A (A^T C A)^-1 A^T R a with A explicit,
// the relative norm of the normal rows' difference over motions a in span(z, rotations x, y),
// sampled on the sphere.
TEST(ReducedSole, PressureEstimateIsTheWorstBondedFaceError) {
  for (const unsigned int degree : {2u, 1u}) {
    const CondensedSole sole = make_sole(CondensationParameters::Form::dense, degree);
    const CondensedSole factored = make_sole(CondensationParameters::Form::factorization, degree);
    const Eigen::MatrixX3d& x = sole.contact_positions();
    const Eigen::MatrixXd& c = sole.compliance();
    const int n = sole.n_contacts();
    const Eigen::Vector3d origin = x.colwise().mean().transpose();
    const Eigen::MatrixXd r = rigid_motion_map(x, origin);
    const Eigen::MatrixXd k_c = c.llt().solve(Eigen::MatrixXd::Identity(3 * n, 3 * n));
    const Eigen::MatrixXd f_full = k_c * r;
    // K_c R: the K_nn route of both forms and the dense one.
    EXPECT_LT(relative_difference(sole.rigid_motion_forces(), f_full), 1e-9);
    EXPECT_LT(relative_difference(factored.rigid_motion_forces(), f_full), 1e-9);
    EXPECT_LT(relative_difference(rigid_motion_forces(x, c, origin), f_full), 1e-9);
    // Motions on the unit sphere of (z, theta_x L, theta_y L), L the sole's half length: a
    // Fibonacci lattice of 20,000 points (the ratio is even in a).
    const double half_length = 0.5 * (x.col(0).maxCoeff() - x.col(0).minCoeff());
    std::vector<Eigen::Matrix<double, 6, 1>> motions;
    for (int i = 0; i < 20000; ++i) {
      const double zc = 1 - (i + 0.5) / 10000.0, rho = std::sqrt(std::max(0.0, 1 - zc * zc));
      const double phi = i * M_PI * (3 - std::sqrt(5.0));
      Eigen::Matrix<double, 6, 1> a = Eigen::Matrix<double, 6, 1>::Zero();
      a[2] = zc;
      a[3] = rho * std::cos(phi) / half_length;
      a[4] = rho * std::sin(phi) / half_length;
      motions.push_back(a);
    }
    const Eigen::VectorXd weights = pressure_weights(node_areas(sole));
    struct Case {
      int g;
      PatchBasis basis;
    };
    for (const Case& k : {Case{1, PatchBasis::bilinear}, Case{2, PatchBasis::bilinear},
                          Case{4, PatchBasis::bilinear}, Case{4, PatchBasis::constant},
                          Case{6, PatchBasis::constant}}) {
      const ReducedSole::ShareMatrix shares =
          ReducedSole::grid_shares(x, k.g, k.g, GridSpacing::chebyshev, k.basis, weights);
      const ReducedSole reduced(x, c, shares);
      const double estimate = pressure_error_estimate(f_full, reduced, origin);
      const Eigen::MatrixXd a(ReducedSole::aggregation(shares));
      const Eigen::MatrixXd c_r = a.transpose() * c * a;
      const Eigen::MatrixXd f_r = a * c_r.fullPivLu().solve(a.transpose() * r);
      double worst = 0;
      for (const auto& m : motions) {
        const Eigen::VectorXd full = f_full * m, red = f_r * m;
        double num = 0, den = 0;
        for (int i = 0; i < n; ++i) {
          num += (red[3 * i + 2] - full[3 * i + 2]) * (red[3 * i + 2] - full[3 * i + 2]);
          den += full[3 * i + 2] * full[3 * i + 2];
        }
        worst = std::max(worst, std::sqrt(num / den));
      }
      const double from_k = pressure_error_estimate(factored.rigid_motion_forces(),
                                                    ReducedSole(factored, shares), origin);
      std::printf("P%u, %s %d x %d (%d contacts): pressure estimate %.4f, worst sampled motion "
                  "%.4f, factorization form %.4f; stiffness estimate %.4f\n",
                  degree, k.basis == PatchBasis::bilinear ? "bilinear" : "constant", k.g, k.g,
                  reduced.n_patches(), estimate, worst, from_k,
                  reduction_error_estimate(sole.rigid_motion_stiffness(), reduced, origin));
      EXPECT_LE(worst, estimate * (1 + 1e-9));
      EXPECT_GE(worst, estimate * (1 - 1e-3));
      EXPECT_NEAR(from_k, estimate, 1e-9 * estimate);
    }
    if (degree == 2)
      continue; // the identity patches and auto below: on the P1 sole
    // One node per patch: the full sole, no error.
    std::vector<int> identity(n);
    for (int i = 0; i < n; ++i)
      identity[i] = i;
    EXPECT_LT(pressure_error_estimate(f_full, ReducedSole(x, c, identity), origin), 1e-9);
    EXPECT_THROW(pressure_error_estimate(f_full.topRows(3), ReducedSole(x, c, identity), origin),
                 std::invalid_argument);
    // auto on the pressure: the coarsest bilinear grid whose pressure estimate meets the
    // tolerance, the next coarser one missing it; the same choice from either form.
    const auto pressure_of = [&](int g) {
      return pressure_error_estimate(
          f_full,
          ReducedSole(x, c,
                      ReducedSole::grid_shares(x, g, g, GridSpacing::chebyshev,
                                               PatchBasis::bilinear, weights)),
          origin);
    };
    for (const double tolerance : {0.5, 0.1, 0.05, 0.03}) {
      const ReductionChoice choice =
          choose_reduction(x, c, tolerance, GridSpacing::chebyshev, weights, PatchBasis::bilinear,
                           ReductionQuantity::pressure);
      const ReductionChoice from_k =
          choose_reduction(factored, tolerance, GridSpacing::chebyshev, weights,
                           PatchBasis::bilinear, ReductionQuantity::pressure);
      std::printf("pressure tolerance %.3g: grid %d, %d contacts, pressure estimate %.4f, "
                  "stiffness estimate %.4f, reached %d\n",
                  tolerance, choice.grid, choice.n_patches, choice.pressure_estimate,
                  choice.estimate, choice.reached);
      EXPECT_EQ(choice.grid, from_k.grid) << tolerance;
      EXPECT_EQ(choice.reached, from_k.reached) << tolerance;
      if (!choice.reached)
        continue;
      EXPECT_LE(choice.pressure_estimate, tolerance);
      EXPECT_EQ(choice.estimate_of(ReductionQuantity::pressure), choice.pressure_estimate);
      EXPECT_NEAR(choice.pressure_estimate, pressure_of(choice.grid), 1e-12);
      EXPECT_NEAR(from_k.pressure_estimate, choice.pressure_estimate, 1e-9);
      if (choice.grid > 1) {
        EXPECT_GT(pressure_of(choice.grid - 1), tolerance) << "a coarser grid meets it";
      }
    }
  }
}

TEST(ReducedSole, RejectsBadInput) {
  Eigen::MatrixX3d x = Eigen::MatrixX3d::Random(4, 3);
  const Eigen::MatrixXd c = Eigen::MatrixXd::Identity(12, 12);
  EXPECT_THROW(ReducedSole(x, c, {0, 1, 2}), std::invalid_argument);
  EXPECT_THROW(ReducedSole(x, c, {0, 2, 2, 0}), std::invalid_argument); // patch 1 empty
  EXPECT_THROW(ReducedSole(x, Eigen::MatrixXd::Identity(9, 9), {0, 0, 0, 0}),
               std::invalid_argument);
  EXPECT_THROW(ReducedSole::grid_patches(x, 0, 2), std::invalid_argument);
  ReducedSole::ShareMatrix half(4, 1); // a column summing to 0.5
  half.insert(0, 0) = 0.5;
  EXPECT_THROW(ReducedSole(x, c, half), std::invalid_argument);
  const ReducedSole one(x, c, {0, 0, 0, 0});
  EXPECT_NEAR(one.compliance()(0, 0), 0.25, 1e-15); // (1/4)^2 * 4 diagonal entries
}

} // namespace
} // namespace plantar::coupling
