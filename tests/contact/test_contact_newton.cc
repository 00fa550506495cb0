// The general Delassus operator, the dense LU, the semismooth Newton solver (its generalized
// Jacobian against finite differences) and the automatic choice, on random problems.
#include "contact/contact_solver.h"
#include "contact/dense_lu.h"
#include "contact/semismooth_newton_solver.h"
#include "contact/symmetry.h"
#include "tests/contact/random_problem.h"

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
