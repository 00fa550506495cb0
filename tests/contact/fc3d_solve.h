#pragma once
// Solving a Siconos-format problem with a Plantar solver to a tolerance on Siconos's error
// measure (shared by tests/contact and bench/contact/fc3d_bench).
//
// Plantar's solvers stop on their own natural-map residual (m/s, max over contacts). The solve
// starts with that tolerance at tolerance * ||q|| / sqrt(n) and, while the error measure
// @p error of the iterate is above @p tolerance, divides it by 10 and continues from the
// iterate (warm start), at most 6 times; iterations and time add up over the rounds. The first
// round starts from @p start (3n impulses, e.g. a run's failed/warm_start.txt) or, when it is
// null, from zero.

#include "contact/contact_solver.h"
#include "tests/contact/siconos_format.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <functional>

namespace plantar::contact::testing {

struct Fc3dSolve {
  SolverResult last; ///< the last round's result (finished_by, switch, status)
  Eigen::VectorXd r; ///< impulses (3n)
  int iterations = 0;
  int rounds = 0;
  double seconds = 0.0;
  double error = 0.0; ///< @p error of r
  bool converged = false;
};

inline Fc3dSolve solve_to_tolerance(const SiconosProblem& source, ContactSolverType type,
                                    double tolerance, int max_iterations,
                                    const std::function<double(const Eigen::VectorXd&)>& error,
                                    NewtonLinearSolve linear = NewtonLinearSolve::automatic,
                                    const Eigen::VectorXd* start = nullptr) {
  ContactProblem problem;
  pose_problem(source, problem);
  ContactSolver solver(problem.n_contacts, 0);
  SolverSettings settings;
  settings.solver = type;
  settings.max_iterations = max_iterations;
  settings.warm_start = start != nullptr;
  settings.newton_linear_solve = linear;
  settings.tolerance = tolerance * std::max(source.q.norm(), 1e-300) /
                       std::sqrt(static_cast<double>(std::max(1, problem.n_contacts)));
  Fc3dSolve out;
  out.r = start != nullptr ? *start : Eigen::VectorXd::Zero(3 * problem.n_contacts);
  for (out.rounds = 1; out.rounds <= 7; ++out.rounds) {
    const auto start = std::chrono::steady_clock::now();
    out.last = solver.solve(problem, settings, out.r);
    out.seconds += std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    out.iterations += out.last.iterations;
    out.error = error(out.r);
    if (out.error <= tolerance || !out.last.converged())
      break;
    settings.warm_start = true;
    settings.tolerance *= 0.1;
  }
  out.converged = out.error <= tolerance;
  return out;
}

} // namespace plantar::contact::testing
