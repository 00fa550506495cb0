// The direct solve of an all-sticking problem (SolverSettings::sticking_direct,
// sticking_solver.cc) against a known sticking solution, the dense W and the
// Gauss-Seidel iteration; when it must refuse (and the iteration starts from the refused
// candidate); contacts sliding; a stiff sole; the kept inverse on ill-conditioned soles.
#include "contact/contact_solver.h"
#include "contact/coulomb_cone.h"
#include "tests/contact/sticking_problem.h"

#include <Eigen/Eigenvalues>

#include <algorithm>
#include <cstdio>
#include <gtest/gtest.h>
#include <random>

namespace pc = plantar::contact;
using plantar::contact::test::sticking_problem;

namespace {
// A warm start inside every cone: p* with p_n scaled by 0.8-1.2 and p_t by 0.5.
Eigen::VectorXd inside_warm_start(const Eigen::VectorXd& solution) {
  Eigen::VectorXd warm = solution;
  for (Eigen::Index k = 0; k < warm.size() / 3; ++k) {
    warm[3 * k] *= 1.0 + 0.2 * std::sin(1.7 * static_cast<double>(k));
    warm.segment<2>(3 * k + 1) *= 0.5;
  }
  return warm;
}

pc::SolverSettings settings_for(pc::ContactSolverType type, bool direct, double tolerance,
                                int rounds = pc::SolverSettings{}.sticking_rounds) {
  pc::SolverSettings settings;
  settings.solver = type;
  settings.sticking_direct = direct;
  settings.sticking_rounds = rounds;
  settings.tolerance = tolerance;
  settings.max_iterations = 100000;
  return settings;
}
} // namespace

TEST(ContactSticking, DirectSolveGivesTheStickingSolution) {
  const int n_nodes = 30, m = 12, n = 2 * n_nodes;
  const auto fixture = sticking_problem(n_nodes, m, 1.0, 0.5, -1, 3);
  const pc::ContactProblem& problem = fixture.problem;
  const Eigen::VectorXd& p_star = fixture.solution;
  Eigen::MatrixXd w;
  problem.assemble_delassus(w);
  pc::ContactSolver solver(n, m);
  for (const auto type : {pc::ContactSolverType::gauss_seidel, pc::ContactSolverType::admm}) {
    Eigen::VectorXd p = inside_warm_start(p_star);
    const pc::SolverResult r = solver.solve(problem, settings_for(type, true, 1e-10), p);
    const double e_p = (p - p_star).norm() / p_star.norm();
    const Eigen::VectorXd v_dense = w * p + problem.free_velocity.head(3 * n);
    const double e_v = (solver.velocity(n) - v_dense).norm() / problem.free_velocity.norm();
    double e_product = 0.0;
    for (const auto& patch : problem.patches) {
      Eigen::VectorXd p_patch = p.segment(3 * patch.first_contact, 3 * patch.n_contacts);
      pc::rotate_to_patch(patch.rotation, p_patch);
      const Eigen::VectorXd dense = patch.compliance_over_dt * p_patch;
      e_product = std::max(e_product, (solver.patch_product(patch) - dense).norm() / dense.norm());
    }
    std::printf("%s, direct %d: |p - p*|/|p*| %.2e, v vs dense W p + v_free %.2e, patch "
                "products %.2e, residual %.2e\n",
                pc::to_string(type), r.direct, e_p, e_v, e_product, r.residual);
    EXPECT_TRUE(r.direct);
    EXPECT_EQ(r.direct_attempt, pc::DirectAttempt::accepted);
    EXPECT_TRUE(r.converged());
    EXPECT_EQ(r.iterations, 0);
    EXPECT_LE(e_p, 1e-11);
    EXPECT_LE(e_v, 1e-12);
    EXPECT_LE(e_product, 1e-11); // the active rows from the sticking equations: their residual
    EXPECT_LE(r.residual, 1e-10);
  }
  // The iteration from the same warm start reaches the same point.
  Eigen::VectorXd p_gs = inside_warm_start(p_star);
  const pc::SolverResult r_gs =
      solver.solve(problem, settings_for(pc::ContactSolverType::gauss_seidel, false, 1e-12), p_gs);
  const double e_gs = (p_gs - p_star).norm() / p_star.norm();
  std::printf("Gauss-Seidel without the direct solve: %d sweeps, |p - p*|/|p*| %.2e\n",
              r_gs.iterations, e_gs);
  EXPECT_FALSE(r_gs.direct);
  EXPECT_GT(r_gs.iterations, 0);
  EXPECT_LE(e_gs, 1e-8);
}

TEST(ContactSticking, RefusedCandidateIsTheIterationStart) {
  // p* has contact 7 outside its cone: the sticking system's solution p* is not a solution of
  // the contact problem. With one active set (sticking_rounds = 1) the iteration starts from
  // p* projected onto the cones (built here densely), with the direct solve's G^T p and patch
  // products, and converges to the same solution as from the warm start.
  const int n_nodes = 25, m = 12, n = 2 * n_nodes;
  const auto fixture = sticking_problem(n_nodes, m, 1.0, 0.4, 7, 5);
  Eigen::VectorXd warm = fixture.solution;
  warm.segment<2>(3 * 7 + 1) *= 0.3; // inside the cone: the direct solve is tried
  Eigen::VectorXd start = fixture.solution;
  start.segment<3>(21) = pc::project_onto_cone(start.segment<3>(21), fixture.problem.friction[7]);
  pc::ContactSolver solver(n, m);
  const auto type = pc::ContactSolverType::gauss_seidel;
  // One sweep: from the refused candidate against from the dense start.
  pc::SolverSettings one = settings_for(type, true, 1e-11, 1);
  one.max_iterations = 1;
  Eigen::VectorXd p_one = warm, p_one_dense = start;
  const pc::SolverResult r_one = solver.solve(fixture.problem, one, p_one);
  one.sticking_direct = false;
  solver.solve(fixture.problem, one, p_one_dense);
  const double e_one = (p_one - p_one_dense).norm() / p_one_dense.norm();
  // To convergence: with and without the direct solve.
  Eigen::VectorXd p_on = warm, p_off = warm;
  const pc::SolverResult r_on =
      solver.solve(fixture.problem, settings_for(type, true, 1e-11, 1), p_on);
  const pc::SolverResult r_off =
      solver.solve(fixture.problem, settings_for(type, false, 1e-11), p_off);
  const double difference = (p_on - p_off).norm() / p_off.norm();
  const Eigen::Vector3d p7 = p_on.segment<3>(21);
  const double slip_ratio = p7.tail<2>().norm() / (fixture.problem.friction[7] * p7[0]);
  std::printf("refused: direct %d; one sweep from it vs from the dense start %.2e; %d vs %d "
              "sweeps (from the warm start), |p_on - p_off|/|p| %.2e, contact 7 |p_t|/(mu p_n) "
              "%.12f, residual %.2e\n",
              r_one.direct, e_one, r_on.iterations, r_off.iterations, difference, slip_ratio,
              r_on.residual);
  EXPECT_FALSE(r_one.direct);
  EXPECT_EQ(r_one.direct_attempt, pc::DirectAttempt::refused_cone);
  EXPECT_EQ(r_one.iterations, 1);
  EXPECT_LE(e_one, 1e-13);
  EXPECT_FALSE(r_on.direct);
  EXPECT_TRUE(r_on.converged());
  EXPECT_TRUE(r_off.converged());
  EXPECT_LE(r_on.iterations, r_off.iterations);
  EXPECT_LE(difference, 1e-9);
  EXPECT_NEAR(slip_ratio, 1.0, 1e-9); // contact 7 slides: on the cone's boundary
  // With the sweep skip, the iteration after the refusal builds W_kk only for the contacts it
  // solves (the lazy path): the result is judged by a dense W p and against p_off.
  pc::SolverSettings skipping = settings_for(type, true, 1e-9, 1);
  skipping.sweep_skip = 0.5;
  Eigen::VectorXd p_skip = warm;
  const pc::SolverResult r_skip = solver.solve(fixture.problem, skipping, p_skip);
  Eigen::MatrixXd w;
  fixture.problem.assemble_delassus(w);
  const Eigen::VectorXd v_skip = w * p_skip + fixture.problem.free_velocity.head(3 * n);
  const double dense = pc::ContactSolver::complementarity_residual(fixture.problem, p_skip, v_skip);
  const double skip_difference = (p_skip - p_off).norm() / p_off.norm();
  std::printf("refused, sweep skip 0.5: %d sweeps, %d local solves of %d, residual by dense W p "
              "%.2e, |p - p_off|/|p| %.2e\n",
              r_skip.iterations, r_skip.n_local_solves, r_skip.iterations * n, dense,
              skip_difference);
  EXPECT_EQ(r_skip.direct_attempt, pc::DirectAttempt::refused_cone);
  EXPECT_TRUE(r_skip.converged());
  EXPECT_LT(r_skip.n_local_solves, r_skip.iterations * n);
  EXPECT_LE(dense, 1e-9 * (1 + 1e-6));
  EXPECT_LE(skip_difference, 1e-6);
}

TEST(ContactSticking, HoldsASlidingContact) {
  // Contact 7's friction coefficient is lowered until p*_7 lies on its cone: p* is still a
  // solution (v_t = 0). The warm start has contact 7 at p*_7 (predicted sliding) and the
  // others inside: the direct solve with contact 7 sliding (p_t = mu p_n d, slip 0) gives p*.
  const int n_nodes = 25, m = 12, n = 2 * n_nodes;
  auto fixture = sticking_problem(n_nodes, m, 1.0, 0.5, -1, 9);
  const Eigen::Vector3d p7_star = fixture.solution.segment<3>(21);
  fixture.problem.friction[7] = p7_star.tail<2>().norm() / p7_star[0];
  Eigen::VectorXd p = inside_warm_start(fixture.solution);
  p.segment<3>(21) = p7_star;
  pc::ContactSolver solver(n, m);
  for (const auto type : {pc::ContactSolverType::gauss_seidel, pc::ContactSolverType::admm}) {
    Eigen::VectorXd p_type = p;
    const pc::SolverResult r =
        solver.solve(fixture.problem, settings_for(type, true, 1e-9), p_type);
    const double e_p = (p_type - fixture.solution).norm() / fixture.solution.norm();
    std::printf("%s, contact 7 sliding: direct %d, |p - p*|/|p*| %.2e, residual %.2e\n",
                pc::to_string(type), r.direct, e_p, r.residual);
    EXPECT_TRUE(r.direct);
    EXPECT_TRUE(r.converged());
    EXPECT_LE(e_p, 1e-10);
    EXPECT_LE(r.residual, 1e-9);
  }
}

TEST(ContactSticking, SolvesSlidingContactsDirectly) {
  // Contacts whose friction coefficient is lowered below their share of p* slide in the
  // solution. From a warm start inside every cone, the active-set rounds find which slide and
  // the Newton iteration their slip directions: the direct solution must be the iteration's
  // (to 1e-9), with every sliding impulse on its cone and its slip against its friction
  // (v_t = -lambda p_t / |p_t|, lambda >= 0, checked with the dense W).
  const int n_nodes = 25, m = 12, n = 2 * n_nodes;
  int n_direct = 0, n_cases = 0, max_sliding = 0;
  double worst_p = 0.0, worst_slip = 0.0, worst_residual = 0.0;
  for (unsigned seed = 1; seed <= 12; ++seed) {
    auto fixture = sticking_problem(n_nodes, m, 1.0, 0.5, -1, seed);
    std::mt19937 rng(seed);
    std::uniform_int_distribution<int> pick(0, n - 1);
    for (int i = 0; i < 2 + static_cast<int>(seed % 6); ++i) // 2 to 7 contacts slide
      fixture.problem.friction[pick(rng)] *= 0.3;
    const Eigen::VectorXd warm = inside_warm_start(fixture.solution);
    pc::ContactSolver solver(n, m);
    Eigen::VectorXd p_direct = warm, p_gs = warm;
    const auto type = pc::ContactSolverType::gauss_seidel;
    const pc::SolverResult r =
        solver.solve(fixture.problem, settings_for(type, true, 1e-11), p_direct);
    const pc::SolverResult r_gs =
        solver.solve(fixture.problem, settings_for(type, false, 1e-11), p_gs);
    std::printf("seed %u: direct %d (%s), %d iterations, residual %.2e; Gauss-Seidel %d sweeps, "
                "residual %.2e\n",
                seed, r.direct, r.direct ? "accepted" : "refused", r.iterations, r.residual,
                r_gs.iterations, r_gs.residual);
    ASSERT_TRUE(r.converged());
    ASSERT_TRUE(r_gs.converged());
    ++n_cases;
    n_direct += r.direct ? 1 : 0;
    worst_p = std::max(worst_p, (p_direct - p_gs).norm() / p_gs.norm());
    Eigen::MatrixXd w;
    fixture.problem.assemble_delassus(w);
    const Eigen::VectorXd v = w * p_direct + fixture.problem.free_velocity.head(3 * n);
    worst_residual = std::max(
        worst_residual, pc::ContactSolver::complementarity_residual(fixture.problem, p_direct, v));
    int sliding = 0;
    for (int k = 0; k < n; ++k) {
      const Eigen::Vector3d p = p_direct.segment<3>(3 * k);
      const Eigen::Vector2d v_t = v.segment<2>(3 * k + 1);
      if (p[0] <= 0.0 || v_t.norm() < 1e-6) // separated or sticking
        continue;
      ++sliding;
      worst_slip = std::max(worst_slip, (v_t.normalized() + p.tail<2>().normalized()).norm());
      EXPECT_NEAR(p.tail<2>().norm(), fixture.problem.friction[k] * p[0], 1e-9);
    }
    max_sliding = std::max(max_sliding, sliding);
  }
  std::printf("sliding contacts (up to %d per case): %d of %d direct, max |p - p_GS|/|p| %.2e, "
              "max |v_t/|v_t| + p_t/|p_t|| %.2e, max residual %.2e\n",
              max_sliding, n_direct, n_cases, worst_p, worst_slip, worst_residual);
  EXPECT_EQ(n_direct, n_cases);
  EXPECT_GE(max_sliding, 3);
  EXPECT_LE(worst_p, 1e-9);
  EXPECT_LE(worst_slip, 1e-8);
  EXPECT_LE(worst_residual, 1e-11);
}

TEST(ContactSticking, NotTriedWithoutStructureOrStickingWarmStart) {
  const int n_nodes = 20, m = 12, n = 2 * n_nodes;
  const auto fixture = sticking_problem(n_nodes, m, 1.0, 0.5, -1, 9);
  pc::ContactSolver solver(n, m);
  const auto type = pc::ContactSolverType::gauss_seidel;
  const auto solve = [&](const pc::ContactProblem& problem, Eigen::VectorXd p, bool direct,
                         int rounds = 1) {
    const pc::SolverResult r = solver.solve(problem, settings_for(type, direct, 1e-10, rounds), p);
    EXPECT_TRUE(r.converged());
    EXPECT_LE((p - fixture.solution).norm() / fixture.solution.norm(), 1e-7);
    EXPECT_EQ(r.direct, r.direct_attempt == pc::DirectAttempt::accepted);
    return r.direct_attempt;
  };
  using pc::DirectAttempt;
  const Eigen::VectorXd warm = inside_warm_start(fixture.solution);
  EXPECT_EQ(solve(fixture.problem, warm, true), DirectAttempt::accepted);
  EXPECT_EQ(solve(fixture.problem, warm, false), DirectAttempt::not_tried); // switched off
  EXPECT_EQ(solve(fixture.problem, Eigen::VectorXd::Zero(3 * n), true),
            DirectAttempt::not_tried); // cold start
  Eigen::VectorXd lifted = warm;
  lifted.segment<3>(3 * 11).setZero(); // one contact predicted open
  // With one active set, tried and refused: the others, carrying its share, leave their
  // cones. With the default rounds the contact closes again and the solve is direct.
  EXPECT_EQ(solve(fixture.problem, lifted, true), DirectAttempt::refused_cone);
  EXPECT_EQ(solve(fixture.problem, lifted, true, 8), DirectAttempt::accepted);
  Eigen::VectorXd on_cone = warm; // one contact predicted sliding (on the cone)
  on_cone.segment<2>(3 * 4 + 1) =
      Eigen::Vector2d(fixture.problem.friction[4] * on_cone[3 * 4], 0.0);
  // It sticks in p*: made to slide (on its cone at the warm start's p_n), it pushes others
  // out of theirs (refused); the next active sets have them right.
  EXPECT_EQ(solve(fixture.problem, on_cone, true), DirectAttempt::refused_cone);
  EXPECT_EQ(solve(fixture.problem, on_cone, true, 8), DirectAttempt::accepted);
  pc::ContactProblem no_map = fixture.problem;
  no_map.patch_levers[1].lever_map_valid = false; // the owner did not set T this step
  EXPECT_EQ(solve(no_map, warm, true), DirectAttempt::not_tried);
  pc::ContactProblem no_structure = fixture.problem;
  no_structure.patch_levers[0].version = 0; // set_sticking_structure not called
  EXPECT_EQ(solve(no_structure, warm, true), DirectAttempt::not_tried);
  // A semi-definite block (a node not held): the factor cannot be built, the solver iterates.
  pc::ContactProblem singular = fixture.problem;
  singular.patches[0].compliance_over_dt.row(0).setZero();
  singular.patches[0].compliance_over_dt.col(0).setZero();
  pc::set_sticking_structure(singular.patch_levers[0], singular.patch_levers[0].lever);
  Eigen::VectorXd p = warm;
  const pc::SolverResult r_singular = solver.solve(singular, settings_for(type, true, 1e-8), p);
  EXPECT_FALSE(r_singular.direct);
  EXPECT_EQ(r_singular.direct_attempt, DirectAttempt::failed);
}

TEST(ContactSticking, StiffSoleStaysWithinTolerance) {
  // Soles 1e3 to 1e7 times stiffer than the rigid coupling (towards the rigid-foot limit: W
  // close to the rank-12 G G^T, condition number up to ~1e9): the direct solution is kept
  // only when its residual meets the tolerance; either way the result does.
  const int n_nodes = 30, m = 12, n = 2 * n_nodes;
  pc::ContactSolver solver(n, m);
  for (const double scale : {1e-3, 1e-5, 1e-7}) {
    const auto fixture = sticking_problem(n_nodes, m, scale, 0.5, -1, 13);
    Eigen::VectorXd p = inside_warm_start(fixture.solution);
    const pc::SolverResult r = solver.solve(
        fixture.problem, settings_for(pc::ContactSolverType::gauss_seidel, true, 1e-8), p);
    const double e_p = (p - fixture.solution).norm() / fixture.solution.norm();
    // v_free = -W p* carries round-off eps |W| |p*|: p* is the solution only to cond(W) eps.
    Eigen::MatrixXd w;
    fixture.problem.assemble_delassus(w);
    const Eigen::VectorXd lambda = Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd>(w).eigenvalues();
    const double bound = 100.0 * lambda.maxCoeff() / lambda.minCoeff() * 2.2e-16;
    std::printf("C/dt^2 scale %.0e: direct %d, %d sweeps, residual %.2e, |p - p*|/|p*| %.2e "
                "(100 cond(W) eps = %.2e)\n",
                scale, r.direct, r.iterations, r.residual, e_p, bound);
    EXPECT_TRUE(r.converged());
    EXPECT_LE(r.residual, 1e-8);
    if (r.direct) {
      EXPECT_LE(e_p, bound);
    }
  }
}

TEST(ContactSticking, ActiveSetsChangingBetweenSolves) {
  // 90 solves on one solver, each with a different set of separated contacts (p* = 0 there,
  // v_n + b > 0): the kept factors of C_AA are updated node by node (and rebuilt after 60
  // updates). Each solution against p*, and against a fresh solver (factor built anew).
  const int n_nodes = 24, m = 12, n = 2 * n_nodes;
  pc::ContactSolver kept(n, m);
  std::mt19937 rng(17);
  std::uniform_int_distribution<int> pick(0, n - 1);
  std::vector<char> separated(n, 0);
  const auto base = sticking_problem(n_nodes, m, 1.0, 0.5, -1, 23);
  int n_direct = 0;
  double worst = 0.0, worst_fresh = 0.0;
  for (int solve = 0; solve < 90; ++solve) {
    for (int flips = 1 + solve % 3; flips > 0; --flips) // 1-3 contacts change state
      separated[pick(rng)] ^= 1;
    if (solve == 40) // a whole sole lifted, then back
      std::fill(separated.begin() + n_nodes, separated.end(), 1);
    if (solve == 41)
      std::fill(separated.begin() + n_nodes, separated.end(), 0);
    auto fixture = base; // same patches (same PatchLever::version): the kept factors apply
    plantar::contact::test::separate_contacts(fixture, separated, 100 + solve);
    Eigen::VectorXd p = inside_warm_start(fixture.solution);
    const auto settings = settings_for(pc::ContactSolverType::gauss_seidel, true, 1e-10);
    const pc::SolverResult r = kept.solve(fixture.problem, settings, p);
    pc::ContactSolver fresh(n, m);
    Eigen::VectorXd p_fresh = inside_warm_start(fixture.solution);
    fresh.solve(fixture.problem, settings, p_fresh);
    n_direct += r.direct;
    EXPECT_TRUE(r.direct) << "solve " << solve;
    EXPECT_TRUE(r.converged());
    worst = std::max(worst, (p - fixture.solution).norm() / fixture.solution.norm());
    worst_fresh = std::max(worst_fresh, (p - p_fresh).norm() / p_fresh.norm());
  }
  std::printf("90 changing active sets: %d direct, max |p - p*|/|p*| %.2e, max |p - p_fresh|/|p| "
              "%.2e\n",
              n_direct, worst, worst_fresh);
  EXPECT_EQ(n_direct, 90);
  EXPECT_LE(worst, 1e-11);
  EXPECT_LE(worst_fresh, 1e-11);
}

TEST(ContactSticking, KeptInverseOnIllConditionedSoles) {
  // Patch blocks of condition number 1e4 and 1e8, 300 solves on one solver with 1-3 contacts
  // changing state each: the kept H = C_AA^-1 goes through ~600 node updates (rebuilt every
  // 60). Each direct solution against a dense Cholesky solve of the same sticking system
  // W_AA p_A = -(v_free + b e_n)_A (independent of H), within 100 cond(W) eps (cond(W_AA) <=
  // cond(W) by interlacing).
  const int n_nodes = 24, m = 12, n = 2 * n_nodes;
  for (const double condition : {1e4, 1e8}) {
    const auto base = sticking_problem(n_nodes, m, 1.0, 0.5, -1, 31, condition);
    Eigen::MatrixXd w;
    base.problem.assemble_delassus(w);
    const Eigen::VectorXd lambda = Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd>(w).eigenvalues();
    const double bound = 100.0 * lambda.maxCoeff() / lambda.minCoeff() * 2.2e-16;
    pc::ContactSolver kept(n, m);
    std::mt19937 rng(41);
    std::uniform_int_distribution<int> pick(0, n - 1);
    std::vector<char> separated(n, 0);
    int n_direct = 0;
    double worst = 0.0;
    for (int solve = 0; solve < 300; ++solve) {
      for (int flips = 1 + solve % 3; flips > 0; --flips)
        separated[pick(rng)] ^= 1;
      auto fixture = base;
      plantar::contact::test::separate_contacts(fixture, separated, 500 + solve);
      Eigen::VectorXd p = inside_warm_start(fixture.solution);
      const pc::SolverResult r = kept.solve(
          fixture.problem, settings_for(pc::ContactSolverType::gauss_seidel, true, 1e-8), p);
      EXPECT_TRUE(r.converged());
      if (!r.direct)
        continue;
      ++n_direct;
      std::vector<int> active;
      for (int k = 0; k < n; ++k)
        if (!separated[k])
          active.push_back(k);
      const int na = static_cast<int>(active.size());
      Eigen::MatrixXd w_aa(3 * na, 3 * na);
      Eigen::VectorXd rhs(3 * na), p_a(3 * na);
      for (int i = 0; i < na; ++i) {
        for (int j = 0; j < na; ++j)
          w_aa.block<3, 3>(3 * i, 3 * j) = w.block<3, 3>(3 * active[i], 3 * active[j]);
        rhs.segment<3>(3 * i) = -fixture.problem.free_velocity.segment<3>(3 * active[i]);
        rhs[3 * i] -= fixture.problem.normal_bias[active[i]];
        p_a.segment<3>(3 * i) = p.segment<3>(3 * active[i]);
      }
      const Eigen::VectorXd reference = w_aa.llt().solve(rhs);
      worst = std::max(worst, (p_a - reference).norm() / reference.norm());
    }
    std::printf("condition %.0e: %d of 300 direct, max |p_A - p_dense|/|p_dense| %.2e (100 "
                "cond(W) eps = %.2e)\n",
                condition, n_direct, worst, bound);
    // Most candidates pass the 1e-8 residual check; at cond 1e8 round-off alone refuses some
    // (300 and 268 of 300 seen, 270 with Eigen's triangular solves): >= 85 % asserted.
    EXPECT_GE(n_direct, 255);
    EXPECT_LE(worst, bound);
  }
}

TEST(ContactSticking, RefusesWhenASeparatedContactCloses) {
  // The warm start predicts contact 5 separated, but the solution presses it (p*_5 > 0): the
  // candidate leaves contact 5 approaching (v_n + b < 0), its residual fails, the solver
  // iterates and finds p*.
  const int n_nodes = 20, m = 12, n = 2 * n_nodes;
  auto fixture = sticking_problem(n_nodes, m, 1.0, 0.5, -1, 29);
  // With the default rounds, the next active set has contact 5 sticking: direct.
  Eigen::VectorXd warm = inside_warm_start(fixture.solution);
  warm.segment<3>(15).setZero();
  pc::ContactSolver solver(n, m);
  for (const int rounds : {1, 8}) {
    Eigen::VectorXd p = warm;
    const pc::SolverResult r = solver.solve(
        fixture.problem, settings_for(pc::ContactSolverType::gauss_seidel, true, 1e-10, rounds), p);
    const double e_p = (p - fixture.solution).norm() / fixture.solution.norm();
    std::printf("separated contact closing, %d active sets: direct %d, %d sweeps, |p - p*|/|p*| "
                "%.2e\n",
                rounds, r.direct, r.iterations, e_p);
    EXPECT_EQ(r.direct, rounds > 1);
    EXPECT_EQ(r.direct_attempt,
              rounds > 1 ? pc::DirectAttempt::accepted : pc::DirectAttempt::refused_residual);
    EXPECT_TRUE(r.converged());
    EXPECT_LE(e_p, 1e-8);
  }
}
