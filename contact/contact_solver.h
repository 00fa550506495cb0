#pragma once
// Solver of the frictional contact problem of contact_problem.h: the facade over the contact
// solvers, each a class with its own workspace sized once for max_contacts:
//  * StickingSolver (sticking_solver.h): the direct solve on the warm start's active set,
//    tried first when settings.sticking_direct and settings.warm_start (not for a problem with
//    a general W, ContactProblem::general); RigidStickingSolver (rigid_sticking_solver.h)
//    instead when no contact is on a compliant patch (W = G G^T);
//  * an IterativeSolver (iterative_solver.h) picked by settings.solver: GaussSeidelSolver
//    (gauss_seidel_solver.h), AdmmSolver (admm_solver.h), SemismoothNewtonSolver
//    (semismooth_newton_solver.h) or AutoSolver (auto_solver.h: GS, then Newton), started from
//    the direct solve's refused candidate and its products, else from the warm start (or zero).
// They share the scales of W and the products of the current impulses through one
// DelassusProducts (delassus_products.h). All report the natural-map residual
// max_k || p_k - P_K(p_k - eta_k vt_k) || / eta_k (m/s), with vt the De Saxce velocity and
// eta_k = 3 / trace(W_kk).
//
// solve() allocates nothing once resize() was called with max_contacts >= n_contacts and the
// problem's rigid rank (tested with Eigen's malloc guard up to 250 contacts in one patch),
// except Newton's sparse LU (NewtonLinearSolve::sparse), taken only for a general W stored
// sparse (third-party problems, never the robot's).

#include "contact/contact_problem.h"
#include "contact/delassus_products.h"
#include "contact/iterative_solver.h"
#include "contact/rigid_sticking_solver.h"
#include "contact/solver_settings.h"
#include "contact/sticking_solver.h"

#include <Eigen/Core>
#include <memory>
#include <vector>

namespace plantar::contact {

class ContactSolver {
public:
  ContactSolver();
  ContactSolver(int max_contacts, int rigid_rank) : ContactSolver() {
    resize(max_contacts, rigid_rank);
  }
  ContactSolver(int max_contacts, int rigid_rank, ContactSolverType type) : ContactSolver() {
    resize(max_contacts, rigid_rank, type);
  }

  /// Sizes the workspaces of every solver type (memory ~ 430 max_contacts^2 bytes: ADMM's
  /// factor and its copy, the direct solve's kept factors, Newton's W, Jacobian and Woodbury
  /// workspace).
  void resize(int max_contacts, int rigid_rank);
  /// Sizes only what @p type needs (the direct solve, and gauss_seidel: GS's; admm: ADMM's
  /// ~144 N^2 bytes; newton: Newton's ~144 N^2 + 8 (3N + m)^2 bytes; automatic: GS's and
  /// Newton's) and frees the others' workspaces: solve() with another type then throws.
  void resize(int max_contacts, int rigid_rank, ContactSolverType type);
  /// solve() accepts @p type (its workspace was sized by the last resize()).
  bool reserved(ContactSolverType type) const;
  int max_contacts() const { return max_contacts_; }

  /// Solves @p problem. @param impulses (>= 3 n_contacts), N s: warm start on
  /// input (if settings.warm_start), solution on output (always in the cones).
  /// Throws std::invalid_argument on bad settings or a problem larger than the
  /// workspace; numerical trouble is reported in the result's status.
  SolverResult solve(const ContactProblem& problem, const SolverSettings& settings,
                     Eigen::Ref<Eigen::VectorXd> impulses);

  /// Contact velocities v = W p + v_free of the last solve (3 n_contacts), m/s.
  Eigen::Ref<const Eigen::VectorXd> velocity(int n_contacts) const {
    return products_.velocity.head(3 * n_contacts);
  }

  /// C_j/dt^2 (I (x) R_j)^T p of the last solve's impulses for @p patch (3 n_contacts of the
  /// patch, m/s, patch frame): pass it back as CompliantPatch::warm_product when the next
  /// solve starts from the same patch-frame impulses (saves one pass over the block).
  Eigen::Ref<const Eigen::VectorXd> patch_product(const CompliantPatch& patch) const {
    return products_.patch_product.segment(3 * patch.first_contact, 3 * patch.n_contacts);
  }

  /// Patch Cholesky factorisations done since resize() (ADMM; reused ones not counted).
  long n_patch_factorizations() const;

  /// Keep the residual of every iteration of the next solves (up to
  /// @p capacity iterations; 0 turns it off). Allocates; for benchmarks.
  void record_history(int capacity) { history_.values.setZero(capacity); }
  /// Residuals (m/s) of iterations 1..n of the last solve, n = min(iterations, capacity).
  Eigen::Ref<const Eigen::VectorXd> history() const { return history_.values.head(history_.size); }

  /// Natural-map residual (m/s, max over contacts) of @p impulses with the velocities
  /// @p velocity = W p + v_free (eta_k from the problem's W_kk).
  static double complementarity_residual(const ContactProblem& problem,
                                         const Eigen::Ref<const Eigen::VectorXd>& impulses,
                                         const Eigen::Ref<const Eigen::VectorXd>& velocity);

private:
  int max_contacts_ = 0;
  int rigid_rank_ = 0;
  DelassusProducts products_;
  StickingSolver sticking_;
  RigidStickingSolver rigid_sticking_;
  // One per ContactSolverType, in the enum's order (make_iterative_solver()).
  std::vector<std::unique_ptr<IterativeSolver>> iterative_;
  std::vector<bool> sized_; // parallel to iterative_: workspace sized by the last resize()
  ResidualHistory history_;
};

} // namespace plantar::contact
