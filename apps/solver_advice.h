#pragma once
// What to change when a contact solve stops a humanoid run (Contact/Failure residual), from
// what the run saw (docs/reliability.md, "Contact solves"). Suggestions, most likely first:
//   1. the solver: admm or gauss-seidel -> Contact/Solver = auto (Gauss-Seidel, then
//      semismooth Newton when it stalls; ADMM is not robust on rank-deficient problems,
//      docs/contact_solvers.md);
//   2. the time step, when the feet are stiff for it: omega dt > 1 with
//      omega = sqrt(2 k / m) (k: one foot's vertical stiffness, both feet on the ground, m: the
//      robot's mass) -> Simulation/Time step = 1 / omega (one significant digit, rounded
//      down); also after non-finite values -> dt / 4;
//   3. the budget, when the solver used it (status max_iterations) -> Contact/Max iterations
//      = 4 x (Newton on redundant contacts may need thousands of iterations: the kestrel walk);
//   4. the tolerance, when the solve stopped just above it (residual <= 100 x Contact/
//      Tolerance) -> Contact/Tolerance = the residual rounded up to one significant digit.

#include "contact/solver_settings.h"

#include <string>

namespace plantar::app {

/// A failed solve and the run around it.
struct SolverFailure {
  contact::SolverResult result;        ///< the solve that failed
  contact::ContactSolverType solver{}; ///< Contact/Solver
  double tolerance = 0;                ///< Contact/Tolerance, m/s
  int max_iterations = 0;              ///< Contact/Max iterations
  double time_step = 0;                ///< Simulation/Time step, s
  double foot_stiffness = 0;           ///< N/m, one foot (HumanoidSummary); 0: rigid
  double robot_mass = 0;               ///< kg
};

/// "try: <setting> (<why>); or <setting> (<why>)...", the most likely remedy first; at least
/// one suggestion.
std::string solver_advice(const SolverFailure& failure);

/// omega dt = dt sqrt(2 k / m) of @p failure (0 for rigid feet).
double stiffness_step_ratio(const SolverFailure& failure);

} // namespace plantar::app
