// newton_linear_bench: semismooth Newton's linear solves (dense LU, Woodbury/Schur) on a
// Plantar-form problem of humanoid size: two soles of n1 and n2 contact nodes (dense SPD
// compliance blocks C/dt^2, rotated) under a rigid factor G = J L^-T of rank m (M = L L^T a
// random SPD mass matrix, J random), every node pressed down.
//
//   newton_linear_bench [n1 63] [n2 394] [m 40] [repeats 3]
//
// Prints per linear solve: iterations, seconds per solve and per iteration (best of the
// repeats), the residual (m/s) and the distance of the impulses to the dense LU's.
#include "contact/contact_solver.h"
#include "contact/semismooth_newton_solver.h"

#include <Eigen/Cholesky>
#include <Eigen/Geometry>
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <random>

namespace pc = plantar::contact;

namespace {
pc::ContactProblem humanoid_problem(int n1, int n2, int m, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> unit(-1.0, 1.0);
  const int n = n1 + n2;
  pc::ContactProblem problem;
  problem.resize(n, m);
  problem.n_contacts = n;
  // M = A A^T / m + I (kg-ish), G = J L^-T.
  Eigen::MatrixXd a(m, m), jac(3 * n, m);
  for (int i = 0; i < a.size(); ++i)
    a.data()[i] = unit(rng);
  for (int i = 0; i < jac.size(); ++i)
    jac.data()[i] = unit(rng);
  const Eigen::MatrixXd mass = a * a.transpose() / m + Eigen::MatrixXd::Identity(m, m);
  const Eigen::LLT<Eigen::MatrixXd> llt(mass);
  problem.rigid_factor = llt.matrixL().solve(jac.transpose()).transpose();
  int first = 0;
  for (const int count : {n1, n2}) {
    pc::CompliantPatch patch;
    patch.first_contact = first;
    patch.n_contacts = count;
    Eigen::MatrixXd b(3 * count, 3 * count);
    for (int i = 0; i < b.size(); ++i)
      b.data()[i] = unit(rng);
    patch.compliance_over_dt = 50.0 * (b * b.transpose() / b.rows() +
                                       0.1 * Eigen::MatrixXd::Identity(3 * count, 3 * count));
    patch.rotation = Eigen::AngleAxisd(0.2 * first, Eigen::Vector3d::UnitY()).toRotationMatrix();
    problem.patches.push_back(patch);
    first += count;
  }
  for (int k = 0; k < n; ++k) {
    problem.friction[k] = 0.8;
    problem.free_velocity[3 * k] = -0.1 + 0.05 * unit(rng);
    problem.free_velocity[3 * k + 1] = 0.02 * unit(rng);
    problem.free_velocity[3 * k + 2] = 0.02 * unit(rng);
  }
  return problem;
}
} // namespace

int main(int argc, char** argv) {
  const int n1 = argc > 1 ? std::atoi(argv[1]) : 63;
  const int n2 = argc > 2 ? std::atoi(argv[2]) : 394;
  const int m = argc > 3 ? std::atoi(argv[3]) : 40;
  const int repeats = argc > 4 ? std::atoi(argv[4]) : 3;
  if (n1 < 1 || n2 < 1 || m < 1 || repeats < 1) {
    std::fprintf(stderr,
                 "newton_linear_bench: n1 = %d, n2 = %d, m = %d, repeats = %d: all must "
                 "be >= 1\n",
                 n1, n2, m, repeats);
    return 1;
  }
  const pc::ContactProblem problem = humanoid_problem(n1, n2, m, 7);
  const int n = problem.n_contacts;
  pc::ContactSolver solver(n, m, pc::ContactSolverType::newton);
  pc::SolverSettings settings;
  settings.solver = pc::ContactSolverType::newton;
  settings.tolerance = 1e-8;
  settings.warm_start = false;
  settings.max_iterations = 200;
  settings.sticking_direct = false;
  std::printf("two soles of %d and %d nodes, rigid rank %d (3n = %d); automatic picks %s\n", n1, n2,
              m, 3 * n,
              pc::to_string(pc::SemismoothNewtonSolver::linear_solve_for(
                  problem, pc::NewtonLinearSolve::automatic)));
  std::printf("%-9s %5s %10s %12s %10s %12s %14s\n", "solve", "iter", "seconds", "s/iteration",
              "residual", "|p-p_dense|", "op. count/it");
  Eigen::VectorXd dense_p;
  for (const auto linear : {pc::NewtonLinearSolve::dense, pc::NewtonLinearSolve::woodbury}) {
    settings.newton_linear_solve = linear;
    double best = 1e300;
    pc::SolverResult result;
    Eigen::VectorXd p;
    for (int rep = 0; rep < repeats; ++rep) {
      p.setZero(3 * n);
      const auto start = std::chrono::steady_clock::now();
      result = solver.solve(problem, settings, p);
      best = std::min(
          best, std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count());
    }
    if (linear == pc::NewtonLinearSolve::dense)
      dense_p = p;
    std::printf("%-9s %5d %10.4f %12.5f %10.2e %12.2e %14.3g\n", pc::to_string(linear),
                result.iterations, best, best / std::max(1, result.iterations), result.residual,
                (p - dense_p).norm() / dense_p.norm(),
                pc::SemismoothNewtonSolver::iteration_cost(problem, linear));
  }
  return 0;
}
