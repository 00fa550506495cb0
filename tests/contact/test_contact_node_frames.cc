// A compliant patch whose nodes each have their own contact frame (CompliantPatch::
// node_rotations: a terrain, contact/terrain.h): W_patch = A C A^T with A = blockdiag(a_i).
// Against the same problem with the block rotated explicitly (A C A^T stored, identity
// rotation) and a dense assembly written out here: the Delassus operator, its products (apply,
// diagonal blocks, traces, patch products and velocities, the Gauss-Seidel update kernel,
// displacements), the semismooth Newton's Woodbury system, and the solutions of every solver
// (Gauss-Seidel, ADMM, Newton, auto, the warm product, the direct sticking solve).
#include "contact/compliance_terms.h"
#include "contact/contact_solver.h"
#include "contact/delassus_products.h"
#include "contact/impulse_change.h"
#include "contact/semismooth_newton_solver.h"
#include "contact/woodbury_newton_system.h"
#include "tests/contact/random_problem.h"
#include "tests/contact/sticking_problem.h"

#include <Eigen/Dense>
#include <Eigen/Geometry>
#include <cstdio>
#include <gtest/gtest.h>
#include <random>

namespace pc = plantar::contact;

namespace {

Eigen::Matrix3d random_rotation(std::mt19937& rng) {
  std::uniform_real_distribution<double> unit(-1.0, 1.0);
  return Eigen::AngleAxisd(2.0 * unit(rng),
                           Eigen::Vector3d(unit(rng), unit(rng), unit(rng)).normalized())
      .toRotationMatrix();
}

// Gives patch @p j of @p problem random per-node rotations.
void set_random_node_rotations(pc::ContactProblem& problem, std::size_t j, unsigned seed) {
  std::mt19937 rng(seed);
  pc::CompliantPatch& patch = problem.patches[j];
  patch.node_rotations.resize(3, 3 * patch.n_contacts);
  for (int i = 0; i < patch.n_contacts; ++i)
    patch.node_rotations.middleCols<3>(3 * i) = random_rotation(rng);
  patch.per_node_rotations = true;
}

// The same problem with every patch block stored as A C A^T (identity rotations).
pc::ContactProblem explicit_blocks(const pc::ContactProblem& problem) {
  pc::ContactProblem out = problem;
  for (pc::CompliantPatch& patch : out.patches) {
    const int size = 3 * patch.n_contacts;
    Eigen::MatrixXd a = Eigen::MatrixXd::Zero(size, size);
    for (int i = 0; i < patch.n_contacts; ++i)
      a.block<3, 3>(3 * i, 3 * i) = patch.node_rotation(i);
    patch.compliance_over_dt = a * patch.compliance_over_dt * a.transpose();
    patch.rotation.setIdentity();
    patch.per_node_rotations = false;
  }
  return out;
}

// W written out: G G^T + sum_j sum_(i, l) a_i C_il a_l^T.
Eigen::MatrixXd dense_delassus(const pc::ContactProblem& problem) {
  const int n3 = 3 * problem.n_contacts;
  const Eigen::MatrixXd g = problem.rigid_factor.topRows(n3);
  Eigen::MatrixXd w = g * g.transpose();
  for (const pc::CompliantPatch& patch : problem.patches)
    for (int i = 0; i < patch.n_contacts; ++i)
      for (int l = 0; l < patch.n_contacts; ++l) {
        const Eigen::Matrix3d a_i = patch.per_node_rotations
                                        ? Eigen::Matrix3d(patch.node_rotations.middleCols<3>(3 * i))
                                        : patch.rotation;
        const Eigen::Matrix3d a_l = patch.per_node_rotations
                                        ? Eigen::Matrix3d(patch.node_rotations.middleCols<3>(3 * l))
                                        : patch.rotation;
        w.block<3, 3>(3 * (patch.first_contact + i), 3 * (patch.first_contact + l)) +=
            a_i * patch.compliance_over_dt.block<3, 3>(3 * i, 3 * l) * a_l.transpose();
      }
  return w;
}

} // namespace

TEST(ContactNodeFrames, DelassusProductsEqualTheDenseAssembly) {
  // 30 contacts: patch 0 on [0, 12) with per-node frames, patch 1 on [14, 26) with one
  // rotation, the others rigid.
  const int n = 30, m = 10;
  pc::ContactProblem problem = pc::test::random_problem(n, m, 12, 0.5, 31);
  pc::CompliantPatch second = problem.patches[0];
  second.first_contact = 14;
  second.rotation = Eigen::AngleAxisd(0.3, Eigen::Vector3d(1.0, 2.0, 3.0).normalized());
  problem.patches.push_back(second);
  set_random_node_rotations(problem, 0, 32);
  ASSERT_NO_THROW(problem.validate());
  const Eigen::MatrixXd w_dense = dense_delassus(problem);
  const pc::ContactProblem reference = explicit_blocks(problem);
  const int n3 = 3 * n;

  Eigen::MatrixXd w, w_reference;
  problem.assemble_delassus(w);
  reference.assemble_delassus(w_reference);
  std::mt19937 rng(33);
  std::uniform_real_distribution<double> unit(-1.0, 1.0);
  Eigen::VectorXd p(n3);
  for (int i = 0; i < n3; ++i)
    p[i] = unit(rng);
  Eigen::VectorXd out(n3), work(std::max(n3, m));
  problem.apply_delassus(p, work, out);
  double e_block = 0, e_trace = 0;
  Eigen::VectorXd traces(n);
  problem.diagonal_traces(traces);
  for (int k = 0; k < n; ++k) {
    const Eigen::Matrix3d dense_block = w_dense.block<3, 3>(3 * k, 3 * k);
    e_block =
        std::max(e_block, (problem.diagonal_block(k) - dense_block).norm() / dense_block.norm());
    e_trace = std::max(e_trace, std::abs(traces[k] - dense_block.trace()) / dense_block.trace());
  }
  // Patch products C A^T p, patch velocities A (C A^T p), the Gauss-Seidel kernel (one
  // contact's change through a_k^T), displacements dt A C A^T p.
  pc::DelassusProducts products;
  products.resize(n, m);
  products.prepare(problem);
  products.velocity.setZero();
  double e_product = 0;
  for (const pc::CompliantPatch& patch : problem.patches) {
    products.compute_patch_product(patch, p);
    const int first = 3 * patch.first_contact, size = 3 * patch.n_contacts;
    Eigen::VectorXd p_patch = p.segment(first, size);
    pc::rotate_to_patch(patch, p_patch);
    const Eigen::VectorXd dense = patch.compliance_over_dt * p_patch;
    e_product = std::max(e_product, (products.patch_product.segment(first, size) - dense).norm() /
                                        dense.norm());
  }
  products.add_patch_velocities(problem);
  Eigen::VectorXd patch_velocity_dense = Eigen::VectorXd::Zero(n3);
  for (const pc::CompliantPatch& patch : problem.patches) {
    const int first = 3 * patch.first_contact, size = 3 * patch.n_contacts;
    patch_velocity_dense.segment(first, size) =
        w_dense.block(first, first, size, size) * p.segment(first, size) -
        (problem.rigid_factor.middleRows(first, size) *
         (problem.rigid_factor.middleRows(first, size).transpose() * p.segment(first, size)));
  }
  // Only the patch part: W_jj p_j minus its rigid part G_j G_j^T p_j.
  const double e_velocity =
      (products.velocity - patch_velocity_dense).norm() / patch_velocity_dense.norm();
  Eigen::VectorXd rigid_work = Eigen::VectorXd::Zero(m);
  Eigen::VectorXd change_product = Eigen::VectorXd::Zero(n3);
  const int k_change = 5;
  const Eigen::Vector3d delta(0.3, -0.2, 0.7);
  pc::add_impulse_change(problem, &problem.patches[0], k_change, delta, rigid_work.data(),
                         change_product.data());
  const Eigen::VectorXd change_dense =
      problem.patches[0].compliance_over_dt.middleCols<3>(3 * k_change) *
      (problem.patches[0].node_rotation(k_change).transpose() * delta);
  const double e_change = (change_product.head(36) - change_dense).norm() / change_dense.norm();
  Eigen::VectorXd u(36), u_reference(36);
  pc::patch_displacement(problem.patches[0], p, 1e-3, u);
  pc::patch_displacement(reference.patches[0], p, 1e-3, u_reference);
  const Eigen::VectorXd u_dense =
      1e-3 * (w_dense.topLeftCorner(36, 36) * p.head(36) -
              problem.rigid_factor.topRows(36) *
                  (problem.rigid_factor.topRows(36).transpose() * p.head(36)));

  const double e_w = (w - w_dense).norm() / w_dense.norm();
  const double e_w_reference = (w_reference - w_dense).norm() / w_dense.norm();
  const double e_apply = (out - w_dense * p).norm() / (w_dense * p).norm();
  const double e_u =
      std::max((u - u_dense).norm(), (u_reference - u_dense).norm()) / u_dense.norm();
  std::printf("per-node frames vs dense: W %.1e (explicit block %.1e), W p %.1e, W_kk %.1e, "
              "trace %.1e, C A^T p %.1e, A C A^T p %.1e, one-contact change %.1e, U %.1e "
              "(tol 1e-13)\n",
              e_w, e_w_reference, e_apply, e_block, e_trace, e_product, e_velocity, e_change, e_u);
  EXPECT_LE(e_w, 1e-14);
  EXPECT_LE(e_w_reference, 1e-14);
  EXPECT_LE(e_apply, 1e-14);
  EXPECT_LE(e_block, 1e-14);
  EXPECT_LE(e_trace, 1e-14);
  EXPECT_LE(e_product, 1e-14);
  EXPECT_LE(e_velocity, 1e-13);
  EXPECT_LE(e_change, 1e-14);
  EXPECT_LE(e_u, 1e-13);

  // Not orthonormal, or too few columns: refused.
  pc::ContactProblem bad = problem;
  bad.patches[0].node_rotations(0, 3) *= 1.01;
  EXPECT_THROW(bad.validate(), std::invalid_argument);
  bad = problem;
  bad.patches[0].node_rotations.resize(3, 9);
  EXPECT_THROW(bad.validate(), std::invalid_argument);
}

TEST(ContactNodeFrames, WoodburyNewtonSystemSolvesTheDenseSystem) {
  const int n = 30, m = 12;
  pc::ContactProblem problem = pc::test::random_problem(n, m, 12, 0.5, 41);
  pc::CompliantPatch second = problem.patches[0];
  second.first_contact = 14;
  problem.patches.push_back(second);
  set_random_node_rotations(problem, 0, 42);
  set_random_node_rotations(problem, 1, 43);
  const int n3 = 3 * n;
  const Eigen::MatrixXd w = dense_delassus(problem);
  pc::WoodburyNewtonSystem woodbury;
  woodbury.resize(n, m);
  Eigen::VectorXd rho(n);
  for (int k = 0; k < n; ++k)
    rho[k] = 3.0 / w.block<3, 3>(3 * k, 3 * k).trace();
  std::mt19937 rng(44);
  std::uniform_real_distribution<double> unit(-1.0, 1.0);
  double worst = 0;
  for (int trial = 0; trial < 6; ++trial) {
    Eigen::VectorXd r(n3), rhs(n3);
    for (int i = 0; i < n3; ++i) {
      r[i] = unit(rng) + (i % 3 == 0 ? 0.3 : 0.0);
      rhs[i] = unit(rng);
    }
    const Eigen::VectorXd v = w * r + problem.free_velocity.head(n3);
    Eigen::MatrixXd a_blocks(3, n3), b_blocks(3, n3);
    std::vector<int> active;
    for (int k = 0; k < n; ++k) {
      Eigen::Vector3d phi;
      Eigen::Matrix3d a, b;
      if (!pc::SemismoothNewtonSolver::contact_function(r.segment<3>(3 * k), v.segment<3>(3 * k),
                                                        problem.friction[k], rho[k], phi, &a, &b))
        active.push_back(k);
      a_blocks.middleCols<3>(3 * k) = a;
      b_blocks.middleCols<3>(3 * k) = b;
    }
    // The Jacobian A + B W restricted to the active contacts, from the dense W.
    const int na = static_cast<int>(active.size());
    Eigen::MatrixXd jaa(3 * na, 3 * na);
    for (int i = 0; i < na; ++i)
      for (int l = 0; l < na; ++l) {
        jaa.block<3, 3>(3 * i, 3 * l) =
            b_blocks.middleCols<3>(3 * active[i]) * w.block<3, 3>(3 * active[i], 3 * active[l]);
        if (i == l)
          jaa.block<3, 3>(3 * i, 3 * i) += a_blocks.middleCols<3>(3 * active[i]);
      }
    const double delta = 1e-10;
    jaa.diagonal().array() += delta;
    const Eigen::VectorXd b = rhs.head(3 * na);
    const Eigen::VectorXd reference = jaa.partialPivLu().solve(b);
    Eigen::VectorXd x = b;
    ASSERT_TRUE(woodbury.factorize(problem, active.data(), na, a_blocks, b_blocks, delta));
    woodbury.solve(problem, x);
    worst = std::max(worst, (x - reference).norm() / reference.norm());
  }
  std::printf("Woodbury Newton system with per-node frames vs dense LU: %.1e (tol 1e-9)\n", worst);
  EXPECT_LE(worst, 1e-9);
}

TEST(ContactNodeFrames, EverySolverGivesTheDenseReferenceSolution) {
  // 16 contacts, the patch on [0, 12) with per-node frames; the reference: the explicit
  // block A C A^T solved by semismooth Newton.
  const int n = 16, m = 8;
  pc::ContactProblem problem = pc::test::random_problem(n, m, 12, 0.5, 21);
  set_random_node_rotations(problem, 0, 52);
  const pc::ContactProblem reference = explicit_blocks(problem);
  pc::ContactSolver solver(n, m);
  pc::SolverSettings settings;
  settings.tolerance = 1e-11;
  settings.max_iterations = 100000;
  settings.warm_start = false;
  settings.solver = pc::ContactSolverType::newton;
  Eigen::VectorXd p_reference = Eigen::VectorXd::Zero(3 * n);
  ASSERT_TRUE(solver.solve(reference, settings, p_reference).converged());
  for (const auto type : {pc::ContactSolverType::gauss_seidel, pc::ContactSolverType::admm,
                          pc::ContactSolverType::newton, pc::ContactSolverType::automatic}) {
    settings.solver = type;
    Eigen::VectorXd p = Eigen::VectorXd::Zero(3 * n);
    const pc::SolverResult result = solver.solve(problem, settings, p);
    const double e_p = (p - p_reference).norm() / p_reference.norm();
    // The solver's patch product C A^T p of its solution.
    Eigen::VectorXd p_patch = p.head(36);
    pc::rotate_to_patch(problem.patches[0], p_patch);
    const Eigen::VectorXd dense = problem.patches[0].compliance_over_dt * p_patch;
    const double e_product =
        (solver.patch_product(problem.patches[0]) - dense).norm() / dense.norm();
    std::printf("%s: converged %d in %d, |p - p_dense| / |p| %.1e (tol 1e-9), patch product "
                "%.1e\n",
                pc::to_string(type), result.converged(), result.iterations, e_p, e_product);
    EXPECT_TRUE(result.converged());
    EXPECT_LE(e_p, 1e-9);
    EXPECT_LE(e_product, 1e-10);
  }
  // The Gauss-Seidel warm product C A^T p0 of a warm start: the same solution.
  settings.solver = pc::ContactSolverType::gauss_seidel;
  settings.warm_start = true;
  Eigen::VectorXd p0 = 0.8 * p_reference;
  Eigen::VectorXd p0_patch = p0.head(36);
  pc::rotate_to_patch(problem.patches[0], p0_patch);
  pc::ContactProblem warm = problem;
  warm.patches[0].warm_product = problem.patches[0].compliance_over_dt * p0_patch;
  warm.patches[0].warm_product_valid = true;
  Eigen::VectorXd p_warm = p0;
  ASSERT_TRUE(solver.solve(warm, settings, p_warm).converged());
  const double e_warm = (p_warm - p_reference).norm() / p_reference.norm();
  std::printf("warm product: |p - p_dense| / |p| %.1e (tol 1e-9)\n", e_warm);
  EXPECT_LE(e_warm, 1e-9);
}

TEST(ContactNodeFrames, DirectStickingSolveWithPerNodeFrames) {
  // The sticking fixture (two soles, rigid rows A Lambda T) with per-node frames: rows
  // a_i Lambda_i T and the block A C A^T; the known sticking solution p*.
  const int n_nodes = 20, m = 12, n = 2 * n_nodes;
  auto fixture = pc::test::sticking_problem(n_nodes, m, 1.0, 0.5, -1, 61);
  pc::ContactProblem& problem = fixture.problem;
  for (std::size_t j = 0; j < 2; ++j) {
    const Eigen::Matrix3d old_rotation = problem.patches[j].rotation;
    set_random_node_rotations(problem, j, 62 + static_cast<unsigned>(j));
    const pc::CompliantPatch& patch = problem.patches[j];
    for (int i = 0; i < n_nodes; ++i) {
      auto rows = problem.rigid_factor.middleRows<3>(3 * (patch.first_contact + i));
      const Eigen::MatrixXd body_rows = old_rotation.transpose() * rows;
      rows = patch.node_rotation(i) * body_rows;
    }
  }
  const Eigen::MatrixXd w = dense_delassus(problem);
  problem.free_velocity.head(3 * n) = -w * fixture.solution;
  for (int k = 0; k < n; ++k)
    problem.free_velocity[3 * k] -= problem.normal_bias[k];
  pc::ContactSolver solver(n, m);
  pc::SolverSettings settings;
  settings.sticking_direct = true;
  settings.tolerance = 1e-10;
  settings.max_iterations = 100000;
  Eigen::VectorXd p = fixture.solution;
  for (int k = 0; k < n; ++k) { // a warm start inside the cones
    p[3 * k] *= 1.1;
    p.segment<2>(3 * k + 1) *= 0.5;
  }
  const pc::SolverResult result = solver.solve(problem, settings, p);
  const double e_p = (p - fixture.solution).norm() / fixture.solution.norm();
  std::printf("direct sticking solve with per-node frames: %s, |p - p*| / |p*| %.1e (tol 1e-10)\n",
              result.direct_attempt == pc::DirectAttempt::accepted ? "accepted" : "not accepted",
              e_p);
  EXPECT_EQ(result.direct_attempt, pc::DirectAttempt::accepted);
  EXPECT_LE(e_p, 1e-10);
}
