#pragma once
// Semismooth Newton on the Alart-Curnier function (ContactSolverType::newton; Alart and Curnier
// 1991, as in Siconos's NSN_AC). With u = W r + v_free + b e_n, per contact k, rho_k > 0:
//
//   a_k        = r_n - rho_k u_n,        w_k = r_t - rho_k u_t,        R_k = mu_k max(0, a_k)
//   Phi_k,n    = r_n - max(0, a_k)
//   Phi_k,t    = r_t - P_D(R_k)(w_k)     (P_D(R): projection onto the disk of radius R)
//
// Phi(r) = 0 iff r solves the contact problem (Coulomb's law; the same solutions as De Saxce's
// formulation used by the residual). Phi is piecewise smooth; an element of its generalized
// Jacobian is J = A + B W with A = dPhi/dr, B = dPhi/du block diagonal (contact_function()).
// Each iteration solves (J + delta I) d = -Phi, delta a small regularisation raised when the line
// search fails or accepts only a short step (W may be rank-deficient), lowered after a full step,
// and takes r += t d with a non-monotone Armijo line search on the merit 0.5 ||Phi||^2 (the
// largest of the last 5 values as reference).
//
// The linear solve eliminates the separated contacts (a_k <= 0: Phi_k = r_k, rows of the
// identity, d_k = -r_k) and factorises the rest densely (LU with partial pivoting, dense_lu.h):
// O((3 n_active)^3) per iteration. W is assembled densely once per solve (any Delassus form).
// rho_k = 3 / trace(W_kk) (the residual's scaling).
//
// resize() allocates two 3N x 3N matrices (~144 N^2 bytes); solve() allocates nothing.

#include "contact/iterative_solver.h"

#include <Eigen/Core>

namespace plantar::contact {

class SemismoothNewtonSolver final : public IterativeSolver {
public:
  void resize(int max_contacts, int rigid_rank) override;
  /// Starts from @p impulses (its own products: @p start is not used). Returns the impulses
  /// projected onto the cones, their velocity and residual.
  SolverResult solve(const ContactProblem& problem, const SolverSettings& settings,
                     Eigen::Ref<Eigen::VectorXd> impulses, DelassusProducts& products,
                     StartProducts start, ResidualHistory& history) override;

  /// Alart-Curnier function of one contact at impulse @p r (N s) and velocity @p u (m/s, the
  /// normal one including the bias b), with mu >= 0 and rho > 0 (N s per m/s): @p phi (N s) and,
  /// when non-null, the blocks of a generalized Jacobian, @p dphi_dr (dimensionless) and
  /// @p dphi_du (N s per m/s). Returns true when the contact is separated (a <= 0: Phi = r).
  static bool contact_function(const Eigen::Vector3d& r, const Eigen::Vector3d& u, double mu,
                               double rho, Eigen::Vector3d& phi, Eigen::Matrix3d* dphi_dr,
                               Eigen::Matrix3d* dphi_du);

  /// Phi (3 n_contacts) and the full generalized Jacobian J = A + B W (3n x 3n) of @p problem at
  /// @p r with the weights @p rho (n), for tests. Needs resize() with at least n_contacts.
  void evaluate(const ContactProblem& problem, const Eigen::Ref<const Eigen::VectorXd>& r,
                const Eigen::Ref<const Eigen::VectorXd>& rho, Eigen::Ref<Eigen::VectorXd> phi,
                Eigen::Ref<Eigen::MatrixXd> jacobian);

private:
  // phi_ of r_ with velocities u_ (v_free included, bias not); returns 0.5 ||phi||^2.
  double merit(const ContactProblem& problem, const Eigen::Ref<const Eigen::VectorXd>& r,
               const Eigen::Ref<const Eigen::VectorXd>& u, Eigen::Ref<Eigen::VectorXd> phi) const;

  Eigen::MatrixXd delassus_;            // 3N x 3N, W
  Eigen::MatrixXd jacobian_;            // 3N x 3N, reduced J + delta I, then its LU factors
  Eigen::VectorXi pivots_;              // 3N
  Eigen::VectorXi active_;              // N, contacts kept in the reduced system
  Eigen::VectorXi separated_;           // N, 1 when a_k <= 0
  Eigen::MatrixXd a_blocks_, b_blocks_; // 3 x 3N, dPhi/dr and dPhi/du per contact
  Eigen::VectorXd rho_, r_, u_, phi_, step_, w_step_, rhs_, trial_r_, trial_u_, trial_phi_;
  Eigen::VectorXd merits_; // the last merits (non-monotone reference)
};

} // namespace plantar::contact
