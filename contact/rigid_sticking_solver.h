#pragma once
// The direct solve on the warm start's active set for rigid contacts (W = G G^T: no compliant
// patch, no general W): the predictor ContactSolver tries before its iterative solver when
// SolverSettings::sticking_direct, as StickingSolver does for compliant patches.
//
// Contacts with p_n > 0 in the warm start p0 are predicted sticking (all three velocity rows
// zero: v_t = 0, v_n = -b), the others separated (p = 0); with no warm start at all, the
// contacts closing under v_free (v_free,n + b < 0) stick. A contact found outside its cone by
// friction is then held on it: its impulse p_n (1, mu d) for a fixed unit tangential d, p_n
// unknown, only its normal velocity row set (v_n = -b). With the equation rows B (|U| x m: the
// rows set) and the impulse rows C (the unknowns' directions, C = B without held contacts):
//   B G^T p = -(v_free + b e_n)_B,   i.e.  B z = r,  r = -(v_free + b e_n + G G^T p0)_B,
// z = G^T dp = C^T x the change of the generalised impulse. Rigid contacts are redundant
// (eight points on a foot, six rigid motions): the impulses are not unique (the net wrench on
// each body is). The solve:
//   C^T C = L L^T            (L m x k, the semi-definite Cholesky factor without its zero
//                             columns: pivots below 1e-10 of the largest diagonal dropped),
//   u = (B L)^+ r            (least squares of least norm by the same factor of (B L)^T B L),
//   z = L u,  x = C L T^-1 u (T = L^T L: the least-norm x with C^T x = z),
// so that without held contacts dp = (G_U G_U^T)^+ r: the solution nearest the warm start
// (continuous in time). One step of iterative refinement follows unless the rows' velocity
// error is already below tolerance / 100.
// Then an active-set round. Friction first: sticking contacts outside their cones by friction
// are held on them, d their tangential direction. Then a contact pulled (p_n < 0) separates
// (and may close again once: no cycling). Once all are in their cones, a separated contact
// closing (v_n + b < -tolerance) joins the sticking ones and a held contact that slips has d
// turned against the slip (-v_t / |v_t|). At most 16 rounds.
// The candidate is kept when the natural-map residual of all contacts meets the tolerance; it
// is then a solution of the contact problem. Otherwise the iterative solver starts from the
// warm start.
//
// Cost per round: O(|U| m^2 + m^3) for the rigid rank m (12 for two feet on the stepper's
// reduced factor). solve() allocates nothing once resize() was called.

#include "contact/delassus_products.h"
#include "contact/solver_settings.h"

#include <Eigen/Core>

namespace plantar::contact {

class RigidStickingSolver {
public:
  /// Sizes the workspace (memory ~ 8 (3 max_contacts m + 3 m^2) bytes).
  void resize(int max_contacts, int rigid_rank);
  /// One attempt from @p impulses (the warm start, in the cones). The result's direct_attempt:
  ///  * accepted: @p impulses hold the solution, the result is final, @p products hold its
  ///    velocity and G^T p;
  ///  * refused_cone (16 rounds without a consistent set, or every contact separated),
  ///    refused_residual, failed (a zero G_U, T not positive definite, a non-finite candidate):
  ///    @p impulses unchanged; @p products' rigid and velocity overwritten;
  ///  * not_tried: the problem has compliant contacts or a general W, or no contact is
  ///    predicted sticking; nothing changed.
  /// @p products must be prepared for @p problem.
  SolverResult solve(const ContactProblem& problem, const SolverSettings& settings,
                     Eigen::Ref<Eigen::VectorXd> impulses, DelassusProducts& products);

private:
  /// Separated (p = 0), sticking (3 unknown rows), normal (the normal row unknown, the impulse
  /// held on the cone: p = p_n (1, mu d), d a unit tangential direction), pulled (separated in
  /// a round; re-added by closing only while pulled fewer than twice).
  enum State { kSeparated = 0, kSticking = 1, kNormal = 2, kPulled = 3 };
  /// (1, mu d) of a held contact @p k.
  Eigen::Vector3d held_direction(const ContactProblem& problem, int k) const;

  int max_contacts_ = 0;
  int rigid_rank_ = 0;
  Eigen::VectorXi state_;                     // N: State of each contact in the current round
  Eigen::VectorXi pulls_;                     // N: times each contact was pulled in this solve
  Eigen::VectorXd direction_;                 // 2N: d of the held contacts
  Eigen::MatrixXd equations_;                 // 3N x m, B
  Eigen::MatrixXd columns_;                   // 3N x m, C
  Eigen::MatrixXd equations_factor_;          // 3N x m, B L
  Eigen::MatrixXd gram_;                      // m x m, C^T C, then its factor in place
  Eigen::MatrixXd factor_;                    // m x m, L in its first k columns
  Eigen::MatrixXd inner_;                     // m x m, T = L^T L and its Cholesky factor
  Eigen::MatrixXd reduced_;                   // m x m, (B L)^T B L, then its factor in place
  Eigen::MatrixXd reduced_factor_;            // m x m, L2 in its first k2 columns
  Eigen::MatrixXd reduced_inner_;             // m x m, T2 = L2^T L2 and its Cholesky factor
  Eigen::VectorXd residual_;                  // 3N, r
  Eigen::VectorXd correction_;                // 3N, r - B z
  Eigen::VectorXd change_;                    // 3N, dp over U
  Eigen::VectorXd candidate_;                 // 3N, p0: the base of the round's impulses
  Eigen::VectorXd new_impulses_;              // 3N, the round's impulses
  Eigen::VectorXd warm_rigid_;                // m, G^T p0
  Eigen::VectorXd rigid_change_;              // m, z
  Eigen::VectorXd u_, work_, work2_, z_work_; // m each
};

} // namespace plantar::contact
