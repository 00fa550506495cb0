// The general Delassus operator, the dense LU, the semismooth Newton solver (its generalized
// Jacobian against finite differences) and the automatic choice, on random problems.
#include "contact/contact_solver.h"
#include "contact/dense_lu.h"
#include "contact/semismooth_newton_solver.h"
#include "contact/sparse_newton_system.h"
#include "contact/symmetry.h"
#include "contact/woodbury_newton_system.h"
#include "tests/contact/random_problem.h"

#include <Eigen/Geometry>
#include <Eigen/LU>
#include <gtest/gtest.h>
#include <random>

namespace pc = plantar::contact;

namespace {

// A problem with a dense general W = A A^T / 3n + 0.05 I (n contacts), random q, mu.
pc::ContactProblem general_problem(int n, unsigned seed, double skew = 0.0) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> unit(-1.0, 1.0);
  Eigen::MatrixXd a(3 * n, 3 * n), s(3 * n, 3 * n);
  for (int i = 0; i < a.size(); ++i) {
    a.data()[i] = unit(rng);
    s.data()[i] = unit(rng);
  }
  Eigen::MatrixXd w =
      a * a.transpose() / (3.0 * n) + 0.05 * Eigen::MatrixXd::Identity(3 * n, 3 * n);
  w += skew * (s - s.transpose()) * w.cwiseAbs().maxCoeff() / 2.0;
  pc::ContactProblem problem;
  problem.resize(n, 0);
  problem.n_contacts = n;
  for (int i = 0; i < 3 * n; ++i)
    problem.free_velocity[i] = unit(rng) - (i % 3 == 0 ? 0.3 : 0.0);
  for (int k = 0; k < n; ++k)
    problem.friction[k] = 0.5 + 0.3 * unit(rng);
  problem.general.set_dense(w);
  return problem;
}

// Plantar's form on n contacts: G (m columns), patch blocks (SPD, rotated) on [0, 12) and
// [14, 26), the other contacts rigid.
pc::ContactProblem two_patch_problem(int n, int m, unsigned seed) {
  pc::ContactProblem problem = plantar::contact::test::random_problem(n, m, 12, 0.5, seed);
  pc::CompliantPatch second = problem.patches[0];
  second.first_contact = 14;
  second.compliance_over_dt *= 2.0;
  second.rotation = Eigen::AngleAxisd(0.3, Eigen::Vector3d(1.0, 2.0, 3.0).normalized());
  problem.patches.push_back(second);
  return problem;
}

// A block-sparse general W: contact k coupled to k +- 1 and k +- 7 (SPD: B B^T + 0.05 I with
// B block-banded), stored sparse.
pc::ContactProblem sparse_problem(int n, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> unit(-1.0, 1.0);
  Eigen::MatrixXd b = Eigen::MatrixXd::Zero(3 * n, 3 * n);
  for (int k = 0; k < n; ++k)
    for (const int l : {k, k + 1, k + 7})
      if (l < n)
        for (int i = 0; i < 3; ++i)
          for (int j = 0; j < 3; ++j)
            b(3 * k + i, 3 * l + j) = unit(rng);
  const Eigen::MatrixXd w =
      b * b.transpose() / 3.0 + 0.05 * Eigen::MatrixXd::Identity(3 * n, 3 * n);
  pc::ContactProblem problem;
  problem.resize(n, 0);
  problem.n_contacts = n;
  for (int i = 0; i < 3 * n; ++i)
    problem.free_velocity[i] = unit(rng) - (i % 3 == 0 ? 0.3 : 0.0);
  for (int k = 0; k < n; ++k)
    problem.friction[k] = 0.5 + 0.3 * unit(rng);
  problem.general.set_sparse(w.sparseView());
  return problem;
}

// The Woodbury/Schur and sparse systems against a dense LU (Eigen's) of J_AA + delta I built
// from the generalized Jacobian of evaluate(), at random points (active sets of all kinds).
TEST(NewtonLinearSolve, WoodburyAndSparseSolveTheDenseSystem) {
  for (int form = 0; form < 2; ++form) {
    const pc::ContactProblem problem =
        form == 0 ? two_patch_problem(30, 30, 41) : sparse_problem(30, 42);
    const int n = problem.n_contacts, n3 = 3 * n;
    pc::SemismoothNewtonSolver newton;
    newton.resize(n, problem.rigid_rank());
    pc::WoodburyNewtonSystem woodbury;
    woodbury.resize(n, problem.rigid_rank());
    pc::SparseNewtonSystem sparse;
    if (form == 1)
      sparse.prepare(problem);
    Eigen::MatrixXd w;
    problem.assemble_delassus(w);
    Eigen::VectorXd rho(n);
    for (int k = 0; k < n; ++k)
      rho[k] = 3.0 / w.block<3, 3>(3 * k, 3 * k).trace();
    std::mt19937 rng(5);
    std::uniform_real_distribution<double> unit(-1.0, 1.0);
    int n_rigid_active = 0;
    for (int trial = 0; trial < 10; ++trial) {
      Eigen::VectorXd r(n3), phi(n3), rhs(n3);
      for (int i = 0; i < n3; ++i) {
        r[i] = unit(rng) + (i % 3 == 0 ? 0.3 : 0.0);
        rhs[i] = unit(rng);
      }
      Eigen::MatrixXd jacobian(n3, n3), a_blocks(3, n3), b_blocks(3, n3);
      newton.evaluate(problem, r, rho, phi, jacobian);
      const Eigen::VectorXd u = w * r + problem.free_velocity.head(n3);
      std::vector<int> active;
      for (int k = 0; k < n; ++k) {
        Eigen::Vector3d phik;
        Eigen::Matrix3d a, b;
        if (!pc::SemismoothNewtonSolver::contact_function(r.segment<3>(3 * k), u.segment<3>(3 * k),
                                                          problem.friction[k], rho[k], phik, &a,
                                                          &b)) {
          active.push_back(k);
          n_rigid_active += form == 0 && (k == 12 || k == 13 || k >= 26);
        }
        a_blocks.middleCols<3>(3 * k) = a;
        b_blocks.middleCols<3>(3 * k) = b;
      }
      const int na = static_cast<int>(active.size());
      const double delta = trial % 2 == 0 ? 1e-12 : 1e-3;
      Eigen::MatrixXd jaa(3 * na, 3 * na);
      for (int i = 0; i < na; ++i)
        for (int l = 0; l < na; ++l)
          jaa.block<3, 3>(3 * i, 3 * l) = jacobian.block<3, 3>(3 * active[i], 3 * active[l]);
      jaa.diagonal().array() += delta;
      const Eigen::VectorXd b = rhs.head(3 * na);
      const Eigen::VectorXd reference = jaa.partialPivLu().solve(b);
      Eigen::VectorXd x = b;
      if (form == 0) {
        ASSERT_TRUE(woodbury.factorize(problem, active.data(), na, a_blocks, b_blocks, delta));
        woodbury.solve(problem, x);
      } else {
        ASSERT_TRUE(sparse.factorize(active.data(), na, a_blocks, b_blocks, delta));
        sparse.solve(x);
      }
      EXPECT_LT((x - reference).norm(), 1e-9 * reference.norm())
          << "form " << form << " trial " << trial << " active " << na;
      EXPECT_LT((jaa * x - b).norm(), 1e-10 * jaa.norm() * x.norm());
    }
    if (form == 0) {
      EXPECT_GT(n_rigid_active, 5); // the Schur system's rigid rows were exercised
    } else {
      EXPECT_LE(sparse.n_analyses(), 10);
      EXPECT_GE(sparse.n_analyses(), 2);
    }
  }
}

// The same Newton iterates whichever linear solve: iteration count, residual history and
// solution to round-off (well-conditioned problems: W positive definite).
TEST(NewtonLinearSolve, SameIteratesAsTheDenseLu) {
  for (int form = 0; form < 2; ++form) {
    const pc::ContactProblem problem =
        form == 0 ? two_patch_problem(30, 30, 43) : sparse_problem(40, 44);
    const pc::NewtonLinearSolve other =
        form == 0 ? pc::NewtonLinearSolve::woodbury : pc::NewtonLinearSolve::sparse;
    const int n = problem.n_contacts;
    pc::ContactSolver solver(n, problem.rigid_rank(), pc::ContactSolverType::newton);
    solver.record_history(100);
    pc::SolverSettings settings;
    settings.solver = pc::ContactSolverType::newton;
    settings.tolerance = 1e-12;
    settings.warm_start = false;
    settings.max_iterations = 100;
    Eigen::VectorXd p_dense = Eigen::VectorXd::Zero(3 * n), p_other = p_dense;
    settings.newton_linear_solve = pc::NewtonLinearSolve::dense;
    const pc::SolverResult dense = solver.solve(problem, settings, p_dense);
    const Eigen::VectorXd history = solver.history();
    settings.newton_linear_solve = other;
    const pc::SolverResult result = solver.solve(problem, settings, p_other);
    ASSERT_TRUE(dense.converged());
    ASSERT_TRUE(result.converged());
    EXPECT_EQ(dense.newton_linear_solve, pc::NewtonLinearSolve::dense);
    EXPECT_EQ(result.newton_linear_solve, other);
    EXPECT_EQ(result.iterations, dense.iterations) << "form " << form;
    ASSERT_EQ(solver.history().size(), history.size());
    for (Eigen::Index i = 0; i + 1 < history.size(); ++i) // the last is below round-off
      EXPECT_NEAR(solver.history()[i], history[i], 1e-6 * history[i] + 1e-12 * history[0])
          << "iteration " << i + 1;
    EXPECT_LT((p_other - p_dense).norm(), 1e-10 * p_dense.norm()) << "form " << form;
    EXPECT_GT(dense.iterations, 3);
  }
}

// automatic picks the sparse LU for a sparse W of low block density, Woodbury for two large
// patches under a small rigid factor, dense otherwise; a form that does not apply falls back.
TEST(NewtonLinearSolve, AutomaticChoiceFollowsTheForm) {
  using pc::NewtonLinearSolve;
  const auto choice = pc::SemismoothNewtonSolver::linear_solve_for;
  const pc::ContactProblem sparse = sparse_problem(60, 45); // blocks: ~5/60 of the pairs
  EXPECT_EQ(choice(sparse, NewtonLinearSolve::automatic), NewtonLinearSolve::sparse);
  EXPECT_EQ(choice(sparse, NewtonLinearSolve::woodbury), NewtonLinearSolve::dense);
  pc::ContactProblem dense_w = sparse;
  dense_w.general.set_dense(Eigen::MatrixXd(sparse.general.sparse()));
  EXPECT_EQ(choice(dense_w, NewtonLinearSolve::automatic), NewtonLinearSolve::dense);
  EXPECT_EQ(choice(dense_w, NewtonLinearSolve::sparse), NewtonLinearSolve::dense);
  // Two soles of 63 and 394 nodes under m = 40: Woodbury; one rigid contact set: dense.
  pc::ContactProblem soles;
  soles.resize(457, 40);
  soles.n_contacts = 457;
  for (const auto& [first, count] : {std::pair{0, 63}, std::pair{63, 394}}) {
    pc::CompliantPatch patch;
    patch.first_contact = first;
    patch.n_contacts = count;
    soles.patches.push_back(patch);
  }
  EXPECT_EQ(choice(soles, NewtonLinearSolve::automatic), NewtonLinearSolve::woodbury);
  EXPECT_LT(pc::SemismoothNewtonSolver::iteration_cost(soles, NewtonLinearSolve::automatic),
            0.8 * pc::SemismoothNewtonSolver::iteration_cost(soles, NewtonLinearSolve::dense));
  soles.patches.clear();
  EXPECT_EQ(choice(soles, NewtonLinearSolve::automatic), NewtonLinearSolve::dense);
}

// A ContactSolver sized for one type holds only that type's workspaces and refuses the others.
TEST(ContactSolverWorkspace, OnlyTheChosenTypeIsSized) {
  const pc::ContactProblem problem = general_problem(6, 51);
  pc::ContactSolver solver(6, 0, pc::ContactSolverType::gauss_seidel);
  EXPECT_TRUE(solver.reserved(pc::ContactSolverType::gauss_seidel));
  EXPECT_FALSE(solver.reserved(pc::ContactSolverType::newton));
  EXPECT_FALSE(solver.reserved(pc::ContactSolverType::automatic));
  pc::SolverSettings settings;
  settings.solver = pc::ContactSolverType::gauss_seidel;
  settings.max_iterations = 2000;
  Eigen::VectorXd p = Eigen::VectorXd::Zero(18);
  EXPECT_TRUE(solver.solve(problem, settings, p).converged());
  settings.solver = pc::ContactSolverType::newton;
  try {
    solver.solve(problem, settings, p);
    FAIL() << "newton has no workspace";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("newton has no workspace"), std::string::npos) << e.what();
  }
  solver.resize(6, 0, pc::ContactSolverType::automatic);
  EXPECT_TRUE(solver.reserved(pc::ContactSolverType::newton));
  EXPECT_FALSE(solver.reserved(pc::ContactSolverType::admm));
  EXPECT_TRUE(solver.solve(problem, settings, p).converged());
  solver.resize(6, 0); // every type
  EXPECT_TRUE(solver.reserved(pc::ContactSolverType::admm));
}

TEST(DenseLu, SolvesLikeEigensPartialPivLu) {
  for (const int n : {5, 64, 150}) {
    std::mt19937 rng(n);
    std::uniform_real_distribution<double> unit(-1.0, 1.0);
    Eigen::MatrixXd a(n, n);
    Eigen::VectorXd b(n);
    for (int i = 0; i < a.size(); ++i)
      a.data()[i] = unit(rng);
    for (int i = 0; i < n; ++i)
      b[i] = unit(rng);
    Eigen::MatrixXd lu = a;
    Eigen::VectorXi pivots(n);
    ASSERT_TRUE(pc::lu_in_place(lu, pivots));
    Eigen::VectorXd x = b;
    pc::lu_solve_in_place(lu, pivots, x);
    const Eigen::VectorXd reference = a.partialPivLu().solve(b);
    EXPECT_LT((x - reference).norm(), 1e-10 * reference.norm()) << "n = " << n;
    EXPECT_LT((a * x - b).norm(), 1e-11 * b.norm() * a.norm()) << "n = " << n;
  }
  Eigen::MatrixXd singular = Eigen::MatrixXd::Zero(3, 3);
  Eigen::VectorXi pivots(3);
  EXPECT_FALSE(pc::lu_in_place(singular, pivots));
}

TEST(GeneralDelassus, ProductsDiagonalAndAssemblyAgreeWithTheMatrix) {
  pc::ContactProblem problem = general_problem(7, 3, 1e-4);
  Eigen::MatrixXd w = problem.general.dense();
  const Eigen::SparseMatrix<double> sparse = w.sparseView();
  for (int storage = 0; storage < 2; ++storage) {
    if (storage == 1)
      problem.general.set_sparse(sparse);
    Eigen::VectorXd p = Eigen::VectorXd::LinSpaced(21, -1.0, 2.0), work(1), out(21);
    problem.apply_delassus(p, work, out);
    EXPECT_LT((out - w * p).norm(), 1e-14 * (w * p).norm());
    for (int k = 0; k < 7; ++k) {
      EXPECT_EQ((problem.diagonal_block(k) - w.block<3, 3>(3 * k, 3 * k)).norm(), 0.0);
      EXPECT_LT(
          (problem.general.contact_rows_times(k, p.data()) - w.middleRows<3>(3 * k) * p).norm(),
          1e-14);
    }
    Eigen::MatrixXd assembled(21, 21), symmetric(21, 21);
    problem.assemble_delassus_into(assembled);
    problem.assemble_delassus_into(symmetric, true);
    EXPECT_LT((assembled - w).norm(), 1e-15 * w.norm());
    EXPECT_LT((symmetric - 0.5 * (w + w.transpose())).norm(), 1e-15 * w.norm());
    Eigen::VectorXd skew = Eigen::VectorXd::Zero(21);
    problem.general.add_skew_product(p, skew);
    EXPECT_LT((skew - 0.5 * (w - w.transpose()) * p).norm(), 1e-15 * w.norm() * p.norm());
    EXPECT_NEAR(problem.general.asymmetry(), pc::relative_asymmetry(w), 1e-15);
  }
}

TEST(GeneralDelassus, AsymmetryIsReportedSymmetrisedOrRefused) {
  const pc::ContactProblem problem = general_problem(4, 5, 2e-4);
  const Eigen::MatrixXd w = problem.general.dense();
  pc::GeneralDelassus general;
  const double asymmetry = general.set_dense(w, pc::AsymmetryPolicy::symmetrise);
  EXPECT_GT(asymmetry, 1e-4);
  EXPECT_LT(asymmetry, 1e-3);
  EXPECT_TRUE(general.symmetric());
  EXPECT_EQ(general.dense(), Eigen::MatrixXd(0.5 * (w + w.transpose())));
  try {
    general.set_dense(w, pc::AsymmetryPolicy::keep, 1e-5);
    FAIL() << "an asymmetry above the limit must be refused";
  } catch (const std::invalid_argument& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find("relative asymmetry"), std::string::npos) << what;
    EXPECT_NE(what.find("limit 1e-05"), std::string::npos) << what;
  }
  EXPECT_THROW(general.set_dense(Eigen::MatrixXd::Zero(4, 4)), std::invalid_argument);
  pc::ContactProblem wrong = general_problem(4, 5);
  wrong.n_contacts = 3;
  EXPECT_THROW(wrong.validate(), std::invalid_argument);
}

// Central differences of Phi against the generalized Jacobian J = A + B W, at random points
// away from the kinks, on a general dense W and on G G^T + a patch; every regime visited.
TEST(SemismoothNewton, JacobianMatchesFiniteDifferences) {
  std::vector<pc::ContactProblem> problems;
  problems.push_back(general_problem(6, 11, 1e-4));
  problems.push_back(plantar::contact::test::random_problem(6, 5, 3, 0.5, 4));
  int n_regimes[3] = {0, 0, 0}; // separated, sticking, sliding
  for (const pc::ContactProblem& problem : problems) {
    const int n = problem.n_contacts, n3 = 3 * n;
    pc::SemismoothNewtonSolver newton;
    newton.resize(n, problem.rigid_rank());
    Eigen::MatrixXd w;
    problem.assemble_delassus(w);
    Eigen::VectorXd rho(n);
    for (int k = 0; k < n; ++k)
      rho[k] = 3.0 / w.block<3, 3>(3 * k, 3 * k).trace();
    std::mt19937 rng(2);
    std::uniform_real_distribution<double> unit(-1.0, 1.0);
    for (int trial = 0; trial < 20; ++trial) {
      Eigen::VectorXd r(n3);
      for (int i = 0; i < n3; ++i)
        r[i] = unit(rng) + (i % 3 == 0 ? 0.3 : 0.0);
      Eigen::VectorXd phi(n3);
      Eigen::MatrixXd jacobian(n3, n3);
      newton.evaluate(problem, r, rho, phi, jacobian);
      const Eigen::VectorXd u = w * r + problem.free_velocity.head(n3);
      for (int k = 0; k < n; ++k) {
        const double a = r[3 * k] - rho[k] * u[3 * k];
        const double radius = problem.friction[k] * a;
        const double norm_w = (r.segment<2>(3 * k + 1) - rho[k] * u.segment<2>(3 * k + 1)).norm();
        ++n_regimes[a <= 0 ? 0 : norm_w <= radius ? 1 : 2];
      }
      const double h = 1e-7;
      Eigen::MatrixXd fd(n3, n3);
      Eigen::VectorXd phi_plus(n3), phi_minus(n3);
      Eigen::MatrixXd unused(n3, n3);
      for (int j = 0; j < n3; ++j) {
        Eigen::VectorXd rp = r, rm = r;
        rp[j] += h;
        rm[j] -= h;
        newton.evaluate(problem, rp, rho, phi_plus, unused);
        newton.evaluate(problem, rm, rho, phi_minus, unused);
        fd.col(j) = (phi_plus - phi_minus) / (2 * h);
      }
      EXPECT_LT((fd - jacobian).cwiseAbs().maxCoeff(), 1e-6 * (1.0 + jacobian.norm()))
          << "trial " << trial;
    }
  }
  EXPECT_GT(n_regimes[0], 10);
  EXPECT_GT(n_regimes[1], 10);
  EXPECT_GT(n_regimes[2], 10);
}

TEST(SemismoothNewton, ContactFunctionVanishesExactlyOnTheThreeKindsOfSolution) {
  const double mu = 0.5, rho = 0.7;
  Eigen::Vector3d phi;
  // Separation: r = 0, u_n > 0.
  EXPECT_TRUE(pc::SemismoothNewtonSolver::contact_function(
      Eigen::Vector3d::Zero(), Eigen::Vector3d(0.2, 0.3, -0.1), mu, rho, phi, nullptr, nullptr));
  EXPECT_EQ(phi.norm(), 0.0);
  // Sticking: u = 0, r inside the cone.
  pc::SemismoothNewtonSolver::contact_function(
      Eigen::Vector3d(1.0, 0.2, 0.1), Eigen::Vector3d::Zero(), mu, rho, phi, nullptr, nullptr);
  EXPECT_EQ(phi.norm(), 0.0);
  // Sliding: u_n = 0, r_t = -mu r_n u_t / ||u_t||.
  pc::SemismoothNewtonSolver::contact_function(Eigen::Vector3d(1.0, -0.3, -0.4),
                                               Eigen::Vector3d(0.0, 0.6, 0.8), mu, rho, phi,
                                               nullptr, nullptr);
  EXPECT_LT(phi.norm(), 1e-15);
}

// Newton and auto solve random problems of both forms to the tolerance; on a full-rank W with
// small mu (unique solution) they find Gauss-Seidel's solution.
TEST(SemismoothNewton, SolvesRandomProblemsLikeGaussSeidel) {
  for (int form = 0; form < 3; ++form) {
    pc::ContactProblem problem =
        form == 0 ? general_problem(12, 21)
        : form == 1
            ? general_problem(12, 22, 3e-4)
            : plantar::contact::test::random_problem(12, 40, 6, 0.5, 23); // m > 3n: full rank
    if (form != 1)
      problem.friction.setConstant(0.3);
    const int n = problem.n_contacts;
    pc::ContactSolver solver(n, problem.rigid_rank());
    pc::SolverSettings settings;
    settings.tolerance = 1e-12;
    settings.max_iterations = 20000;
    settings.warm_start = false;
    Eigen::VectorXd reference = Eigen::VectorXd::Zero(3 * n);
    settings.solver = pc::ContactSolverType::gauss_seidel;
    ASSERT_TRUE(solver.solve(problem, settings, reference).converged()) << "form " << form;
    for (const auto type : {pc::ContactSolverType::newton, pc::ContactSolverType::automatic,
                            pc::ContactSolverType::admm}) {
      settings.solver = type;
      settings.max_iterations = type == pc::ContactSolverType::admm ? 20000 : 100;
      Eigen::VectorXd p = Eigen::VectorXd::Zero(3 * n);
      const pc::SolverResult result = solver.solve(problem, settings, p);
      EXPECT_TRUE(result.converged())
          << pc::to_string(type) << " form " << form << " residual " << result.residual;
      const double residual =
          pc::ContactSolver::complementarity_residual(problem, p, solver.velocity(n));
      EXPECT_LE(residual, 1e-12);
      EXPECT_LT((p - reference).norm(), 1e-8 * reference.norm())
          << pc::to_string(type) << " form " << form;
      if (type == pc::ContactSolverType::newton) {
        EXPECT_EQ(result.finished_by, pc::ContactSolverType::newton);
        EXPECT_LT(result.iterations, 30);
      }
    }
  }
}

// The automatic choice stays with Gauss-Seidel on an easy problem and records the switch on a
// slow one (a stiff compliant patch on a rigid factor: GS's rate near 1).
TEST(AutoSolver, RecordsWhichSolverFinishedAndWhy) {
  pc::ContactProblem easy = general_problem(5, 31);
  easy.general.set_dense(Eigen::MatrixXd(easy.general.dense()).diagonal().asDiagonal() *
                         Eigen::MatrixXd::Identity(15, 15));
  pc::ContactSolver solver(40, 0);
  pc::SolverSettings settings;
  settings.solver = pc::ContactSolverType::automatic;
  settings.tolerance = 1e-12;
  settings.warm_start = false;
  Eigen::VectorXd p = Eigen::VectorXd::Zero(120);
  pc::SolverResult result = solver.solve(easy, settings, p);
  EXPECT_TRUE(result.converged());
  EXPECT_EQ(result.finished_by, pc::ContactSolverType::gauss_seidel);
  EXPECT_EQ(result.switch_reason, pc::SwitchReason::none);

  // Nearly dependent contacts: W = v v^T + eps I on 40 contacts converges slowly under GS.
  pc::ContactProblem hard = general_problem(40, 32);
  Eigen::MatrixXd w = Eigen::MatrixXd::Constant(120, 120, 0.0);
  for (int k = 0; k < 40; ++k)
    for (int l = 0; l < 40; ++l)
      w(3 * k, 3 * l) = 1.0;
  w += 1e-4 * Eigen::MatrixXd::Identity(120, 120);
  hard.general.set_dense(w);
  for (int k = 0; k < 40; ++k)
    hard.free_velocity[3 * k] = -1.0 - 0.01 * k;
  settings.max_iterations = 2000;
  solver.record_history(4000);
  result = solver.solve(hard, settings, p);
  EXPECT_TRUE(result.converged()) << result.residual;
  EXPECT_EQ(result.finished_by, pc::ContactSolverType::newton);
  EXPECT_NE(result.switch_reason, pc::SwitchReason::none);
  EXPECT_GT(result.switch_iteration, 0);
  EXPECT_GT(result.switch_rate, 0.0);
  EXPECT_EQ(solver.history().size(), result.iterations); // GS sweeps then Newton iterations
  settings.solver = pc::ContactSolverType::gauss_seidel;
  Eigen::VectorXd q = Eigen::VectorXd::Zero(120);
  const pc::SolverResult gs = solver.solve(hard, settings, q);
  EXPECT_GT(gs.iterations, result.iterations); // GS alone is slower (or fails)
}

} // namespace
