#pragma once
// The interface of the iterative contact solvers (gauss_seidel_solver.h, admm_solver.h,
// semismooth_newton_solver.h, auto_solver.h), each
// with its own workspace; ContactSolver (contact_solver.h) picks one by ContactSolverType.

#include "contact/contact_problem.h"
#include "contact/delassus_products.h"
#include "contact/solver_settings.h"

#include <Eigen/Core>

namespace plantar::contact {

/// Where the products of an iteration's start come from.
enum class StartProducts {
  build, ///< the solver builds what it needs from the impulses (and CompliantPatch::warm_product)
  held,  ///< DelassusProducts::rigid and patch_product are those of the impulses (the direct
         ///< solve's refused candidate, sticking_solver.h)
};

/// Residual of each iteration of a solve, up to a capacity (0: none kept).
struct ResidualHistory {
  Eigen::VectorXd values;
  int size = 0;
  /// Added to the iteration numbers recorded (a solver run after another continues its count).
  int offset = 0;
  void record(int iteration, double value) {
    iteration += offset;
    if (iteration >= 1 && iteration <= values.size()) {
      values[iteration - 1] = value;
      size = iteration;
    }
  }
};

class IterativeSolver {
public:
  virtual ~IterativeSolver() = default;
  /// Sizes the solver's workspace; solve() allocates nothing afterwards.
  virtual void resize(int max_contacts, int rigid_rank) = 0;
  /// Iterates from @p impulses (3 n_contacts, in the cones) to the solution of @p problem
  /// (written back to @p impulses). @p products: prepared for @p problem (prepare()), with
  /// @p start saying whether its rigid and patch products are those of @p impulses; on return
  /// velocity and patch_product are those of the returned impulses. Records each iteration's
  /// residual in @p history.
  virtual SolverResult solve(const ContactProblem& problem, const SolverSettings& settings,
                             Eigen::Ref<Eigen::VectorXd> impulses, DelassusProducts& products,
                             StartProducts start, ResidualHistory& history) = 0;
  /// Patch factorisations done since resize() (0 for a solver that factorises nothing).
  virtual long n_patch_factorizations() const { return 0; }
};

} // namespace plantar::contact
