// No heap allocation in the per-step functions once the workspaces are sized
// (Eigen's malloc guard). This executable compiles the plantar_contact sources
// itself with EIGEN_RUNTIME_NO_MALLOC and assertions on (see CMakeLists.txt),
// so an allocation anywhere inside them aborts the test.
#include "contact/compliance_terms.h"
#include "contact/contact_solver.h"
#include "contact/position_correction.h"
#include "tests/contact/random_problem.h"
#include "tests/contact/sticking_problem.h"

#include <cmath>
#include <cstdio>
#include <gtest/gtest.h>
#include <utility>

#ifndef EIGEN_RUNTIME_NO_MALLOC
#error "this test needs EIGEN_RUNTIME_NO_MALLOC"
#endif

namespace pc = plantar::contact;

TEST(ContactNoMalloc, SolveAndHelpersDoNotAllocate) {
  const int max_contacts = 60, m = 12;
  // Largest problem first to size patch matrices, then smaller ones reuse them.
  pc::ContactProblem problem =
      plantar::contact::test::random_problem(max_contacts, m, max_contacts, 0.5, 7);
  pc::ContactSolver solver(max_contacts, m);
  Eigen::VectorXd impulses = Eigen::VectorXd::Zero(3 * max_contacts);
  Eigen::VectorXd work(m), out(3 * max_contacts), displacement(3 * max_contacts);
  const Eigen::MatrixXd compliance = problem.patches[0].compliance_over_dt * 1e-6;
  pc::NormalBiasParameters bias;
  int n_solves = 0;
  for (const int n : {60, 45, 20}) {
    problem.n_contacts = n;
    problem.patches[0].n_contacts = n;
    // Shrinking the patch: keep the leading block (done outside the guard).
    const int size = 3 * problem.patches[0].n_contacts;
    Eigen::MatrixXd patch = compliance.topLeftCorner(size, size) * 1e6;
    problem.patches[0].compliance_over_dt = patch;
    const Eigen::MatrixXd patch_compliance = patch * 1e-6; // C (m/N) for dt = 1e-3
    for (const auto type : {pc::ContactSolverType::gauss_seidel, pc::ContactSolverType::admm})
      for (const bool warm : {false, true}) {
        pc::SolverSettings settings;
        settings.solver = type;
        settings.warm_start = warm;
        settings.max_iterations = 3000;
        Eigen::internal::set_is_malloc_allowed(false);
        const pc::SolverResult r = solver.solve(problem, settings, impulses);
        problem.apply_delassus(impulses, work, out);
        const double b = pc::normal_bias(-1e-4, -0.3, 1e-3, bias);
        pc::set_patch_compliance(problem.patches[0], patch_compliance, 1e-3); // same size: no alloc
        pc::patch_displacement(problem.patches[0], impulses, 1e-3, displacement);
        pc::add_deformation_rate_term(problem.patches[0], displacement.head(size), 1e-3, problem);
        Eigen::internal::set_is_malloc_allowed(true);
        ++n_solves;
        std::printf("n = %d, %s, warm %d: status %s, %d iterations, residual %.2e (b = %.2f)\n", n,
                    pc::to_string(type), warm, pc::to_string(r.status), r.iterations, r.residual,
                    b);
        EXPECT_TRUE(r.converged());
      }
  }
  EXPECT_EQ(n_solves, 12);
}

TEST(ContactNoMalloc, NewtonAndAutoDoNotAllocate) {
  // Shrinking problems (60, 45, 20 contacts, one patch) in one workspace, cold and warm.
  const int max_contacts = 60, m = 12;
  pc::ContactProblem problem =
      plantar::contact::test::random_problem(max_contacts, m, max_contacts, 0.5, 7);
  pc::ContactSolver solver(max_contacts, m);
  Eigen::VectorXd impulses = Eigen::VectorXd::Zero(3 * max_contacts);
  const Eigen::MatrixXd compliance = problem.patches[0].compliance_over_dt;
  for (const int n : {60, 45, 20}) {
    problem.n_contacts = n;
    problem.patches[0].n_contacts = n;
    problem.patches[0].compliance_over_dt = compliance.topLeftCorner(3 * n, 3 * n);
    for (const auto type : {pc::ContactSolverType::newton, pc::ContactSolverType::automatic})
      for (const bool warm : {false, true}) {
        pc::SolverSettings settings;
        settings.solver = type;
        settings.warm_start = warm;
        // Newton's linear solve: the Woodbury/Schur form, automatic (dense here) for auto.
        settings.newton_linear_solve = type == pc::ContactSolverType::newton
                                           ? pc::NewtonLinearSolve::woodbury
                                           : pc::NewtonLinearSolve::automatic;
        settings.max_iterations = 3000;
        Eigen::internal::set_is_malloc_allowed(false);
        const pc::SolverResult r = solver.solve(problem, settings, impulses);
        Eigen::internal::set_is_malloc_allowed(true);
        std::printf("n = %d, %s, warm %d: status %s, %d iterations, residual %.2e, linear %s\n", n,
                    pc::to_string(type), warm, pc::to_string(r.status), r.iterations, r.residual,
                    pc::to_string(r.newton_linear_solve));
        EXPECT_TRUE(r.converged());
      }
  }
}

TEST(ContactNoMalloc, LargePatchFactorisationDoesNotAllocate) {
  // 250 contacts in one dense patch (750 x 750 factor): Eigen's blocked LLT
  // would take heap scratch here; the solver's in-place Cholesky must not.
  const int n = 250, m = 6;
  pc::ContactProblem problem = plantar::contact::test::random_problem(n, m, n, 0.5, 3);
  pc::ContactSolver solver(n, m);
  Eigen::VectorXd impulses = Eigen::VectorXd::Zero(3 * n);
  for (const auto type : {pc::ContactSolverType::gauss_seidel, pc::ContactSolverType::admm,
                          pc::ContactSolverType::newton}) {
    pc::SolverSettings settings;
    settings.solver = type;
    settings.max_iterations = type == pc::ContactSolverType::newton ? 3 : 20;
    settings.rho_update_interval = 2; // force refactorisations
    Eigen::internal::set_is_malloc_allowed(false);
    const pc::SolverResult r = solver.solve(problem, settings, impulses);
    Eigen::internal::set_is_malloc_allowed(true);
    std::printf("n = %d, %s: status %s after %d iterations, residual %.2e, %d factorisations\n", n,
                pc::to_string(type), pc::to_string(r.status), r.iterations, r.residual,
                r.n_factorizations);
    EXPECT_NE(r.status, pc::SolverStatus::non_finite);
  }
}

TEST(ContactNoMalloc, StickingDirectSolveDoesNotAllocate) {
  // Two soles of 40 nodes, every contact sticking: the direct solve (accepted); contact 3
  // outside its cone: accepted with contacts sliding (active-set rounds, the slip's Newton
  // iteration), or refused with one active set; all under the guard.
  const int n_nodes = 40, m = 12, n = 2 * n_nodes;
  pc::ContactSolver solver(n, m);
  for (const auto [outside, rounds] : {std::pair{-1, 8}, std::pair{3, 8}, std::pair{3, 1}}) {
    const auto fixture = plantar::contact::test::sticking_problem(n_nodes, m, 1.0, 0.5, outside, 4);
    Eigen::VectorXd impulses = 0.9 * fixture.solution;
    impulses.segment<2>(3 * 3 + 1) *= 0.3;
    pc::SolverSettings settings;
    settings.solver = pc::ContactSolverType::gauss_seidel;
    settings.max_iterations = 3000;
    settings.sticking_rounds = rounds;
    Eigen::internal::set_is_malloc_allowed(false);
    const pc::SolverResult r = solver.solve(fixture.problem, settings, impulses);
    Eigen::internal::set_is_malloc_allowed(true);
    std::printf("sticking, contact %d outside, %d active sets: direct %d, %d sweeps, residual "
                "%.2e\n",
                outside, rounds, r.direct, r.iterations, r.residual);
    EXPECT_EQ(r.direct, rounds > 1);
    EXPECT_TRUE(r.converged());
  }
}

TEST(ContactNoMalloc, RigidStickingDirectSolveDoesNotAllocate) {
  // 16 rigid contacts of rank 12 (two feet): the direct solve under the guard.
  // Two feet of 8 outline points each: G_k = [I, -[r_k]x] of its foot times a mass factor.
  const int n = 16, m = 12;
  pc::ContactProblem problem;
  problem.resize(n, m);
  problem.n_contacts = n;
  Eigen::MatrixXd lever = Eigen::MatrixXd::Zero(3 * n, m);
  for (int k = 0; k < n; ++k) {
    const int foot = k / 8, corner = k % 8;
    const Eigen::Vector3d r(0.11 * std::cos(0.785 * corner), 0.07 * std::sin(0.785 * corner), 0.0);
    Eigen::Matrix3d skew;
    skew << 0, -r.z(), r.y(), r.z(), 0, -r.x(), -r.y(), r.x(), 0;
    Eigen::Matrix3d frame; // rows n = z, t1 = x, t2 = y of the world
    frame << 0, 0, 1, 1, 0, 0, 0, 1, 0;
    lever.block<3, 3>(3 * k, 6 * foot) = frame;
    lever.block<3, 3>(3 * k, 6 * foot + 3) = -frame * skew;
    problem.free_velocity.segment<3>(3 * k) = Eigen::Vector3d(-0.01, 0.0, 0.0);
    problem.friction[k] = 0.8;
  }
  Eigen::MatrixXd mass_factor = Eigen::MatrixXd::Identity(m, m);
  for (int i = 0; i < m; ++i)
    for (int j = 0; j < i; ++j)
      mass_factor(i, j) = 0.05 * std::sin(1.3 * i + 0.7 * j);
  problem.rigid_factor = lever * mass_factor;
  pc::ContactSolver solver(n, m);
  pc::SolverSettings settings;
  settings.solver = pc::ContactSolverType::automatic;
  settings.max_iterations = 3000;
  Eigen::VectorXd impulses = Eigen::VectorXd::Zero(3 * n);
  ASSERT_TRUE(solver.solve(problem, settings, impulses).converged());
  // Scaled v_free from the converged warm start, then no warm start: both taken directly; a
  // sideways kick at one contact then takes the refusing rounds (held, pulled, closing).
  for (const int variant : {0, 1, 2}) {
    problem.free_velocity.head(3 * n) *= 1.01;
    if (variant == 1)
      impulses.setZero();
    if (variant == 2)
      problem.free_velocity[4] += 0.02;
    Eigen::internal::set_is_malloc_allowed(false);
    const pc::SolverResult r = solver.solve(problem, settings, impulses);
    Eigen::internal::set_is_malloc_allowed(true);
    std::printf("rigid, variant %d: direct %s, %d iterations, residual %.2e\n", variant,
                pc::to_string(r.direct_attempt), r.iterations, r.residual);
    if (variant < 2) {
      EXPECT_TRUE(r.direct);
    }
    EXPECT_TRUE(r.converged());
  }
}

TEST(ContactNoMalloc, GeneralDelassusSolvesDoNotAllocate) {
  // A dense and a sparse general W (non-symmetric, 2e-4), every solver, with the malloc guard.
  const int n = 30;
  pc::ContactProblem problem = plantar::contact::test::random_problem(n, 0, 0, 0.5, 9);
  Eigen::MatrixXd a = Eigen::MatrixXd::Random(3 * n, 3 * n);
  Eigen::MatrixXd w = a * a.transpose() / (3.0 * n) + 0.1 * Eigen::MatrixXd::Identity(3 * n, 3 * n);
  w(0, 1) += 2e-4 * w.cwiseAbs().maxCoeff();
  pc::ContactSolver solver(n, 0);
  Eigen::VectorXd impulses = Eigen::VectorXd::Zero(3 * n);
  for (int storage = 0; storage < 2; ++storage) {
    if (storage == 0)
      problem.general.set_dense(w);
    else
      problem.general.set_sparse(w.sparseView());
    for (const auto type : {pc::ContactSolverType::gauss_seidel, pc::ContactSolverType::admm,
                            pc::ContactSolverType::newton, pc::ContactSolverType::automatic}) {
      pc::SolverSettings settings;
      settings.solver = type;
      settings.warm_start = false;
      settings.max_iterations = 3000;
      settings.tolerance = 1e-10;
      Eigen::internal::set_is_malloc_allowed(false);
      const pc::SolverResult r = solver.solve(problem, settings, impulses);
      Eigen::internal::set_is_malloc_allowed(true);
      std::printf("general %s, %s: %s after %d iterations, residual %.2e\n",
                  storage ? "sparse" : "dense", pc::to_string(type), pc::to_string(r.status),
                  r.iterations, r.residual);
      EXPECT_TRUE(r.converged());
    }
  }
}
