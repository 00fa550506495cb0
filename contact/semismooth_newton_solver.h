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
// Each iteration solves (J + delta I) d = -Phi and takes r += t d with a non-monotone Armijo
// line search on the merit 0.5 ||Phi||^2 (the largest of the last 5 values as reference).
// delta = max(delta_h, delta_LM):
//   delta_LM = min(1e-2, ||Phi|| / (||r|| + ||Phi||))   (a Levenberg-Marquardt-type floor: large
//              far from a solution, vanishing with ||Phi|| near one, where W may be
//              rank-deficient and the solutions not isolated);
//   delta_h  in [1e-12, 1e-2], raised 100x when the line search fails, 10x when it accepts only
//              a step shorter than 1e-4, lowered 10x after a full step.
// With the floor Newton solves every shared fc3d problem from zero, KaplasTower included
// (docs/contact_solvers.md); without it, it failed there.
//
// The linear solve eliminates the separated contacts (a_k <= 0: Phi_k = r_k, rows of the
// identity, d_k = -r_k) and solves for the rest (settings.newton_linear_solve), by
//  * dense:    LU with partial pivoting of J_AA (dense_lu.h), W assembled densely once per solve;
//              (2/3) (3 n_A)^3 operations per iteration;
//  * sparse:   sparse LU of the block-sparse J_AA (sparse_newton_system.h), for a general W stored
//              sparse (third-party problems); allocates (never the robot's path);
//  * woodbury: per-patch LU and a Schur system of size 3 n_rigid + m for W = G G^T + patches
//              (woodbury_newton_system.h);
//  * automatic: sparse when it applies and W's block density is <= kSparseDensity, woodbury
//              when it applies and its operation count (all contacts active) is below the
//              dense one, else dense (linear_solve_for()).
// Products with W go through ContactProblem::apply_delassus (low rank for G G^T).
// rho_k = 3 / trace(W_kk) (the residual's scaling).
//
// resize() allocates W and J densely (two 3N x 3N matrices, ~144 N^2 bytes) and the Woodbury
// workspace ((3N + m)^2 + 3N m doubles); solve() allocates nothing except on the sparse path.

#include "contact/iterative_solver.h"
#include "contact/sparse_newton_system.h"
#include "contact/woodbury_newton_system.h"

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

  /// The linear solve @p requested resolves to for @p problem (automatic: by cost, see above;
  /// a form that does not apply: dense).
  static NewtonLinearSolve linear_solve_for(const ContactProblem& problem,
                                            NewtonLinearSolve requested);
  /// Operation count of one iteration's factorisation by @p solve with every contact active
  /// (the sparse one: kSparseBlockCost per stored 3 x 3 block of W).
  static double iteration_cost(const ContactProblem& problem, NewtonLinearSolve solve);
  /// Block density of W up to which automatic takes the sparse LU (a rough rule: the sparse LU
  /// is 12 to 35x faster per iteration at densities 0.02 to 0.04, equal at 0.18, 2x slower at
  /// 0.29 to 0.33; near 0.2 with n ~ 50 the fill decides, docs/contact_solvers.md).
  static constexpr double kSparseDensity = 0.2;
  /// Operations charged per stored block of W for a sparse LU (fill-in and overhead included;
  /// calibrated against Gauss-Seidel sweeps on Capsules and Confeti: 1,200 and 130).
  static constexpr double kSparseBlockCost = 300.0;

private:
  // phi_ of r_ with velocities u_ (v_free included, bias not); returns 0.5 ||phi||^2.
  double merit(const ContactProblem& problem, const Eigen::Ref<const Eigen::VectorXd>& r,
               const Eigen::Ref<const Eigen::VectorXd>& u, Eigen::Ref<Eigen::VectorXd> phi) const;

  // (J_AA + delta I) d = rhs_ in place on rhs_ by the chosen solve; false on a zero pivot.
  bool solve_linear(const ContactProblem& problem, NewtonLinearSolve solve, int n_active,
                    double delta);

  Eigen::MatrixXd delassus_;            // 3N x 3N, W (dense solve)
  Eigen::MatrixXd jacobian_;            // 3N x 3N, reduced J + delta I, then its LU factors
  Eigen::VectorXi pivots_;              // 3N
  Eigen::VectorXi active_;              // N, contacts kept in the reduced system
  Eigen::VectorXi separated_;           // N, 1 when a_k <= 0
  Eigen::MatrixXd a_blocks_, b_blocks_; // 3 x 3N, dPhi/dr and dPhi/du per contact
  Eigen::VectorXd rho_, r_, u_, phi_, step_, w_step_, rhs_, trial_r_, trial_u_, trial_phi_;
  Eigen::VectorXd merits_;     // the last merits (non-monotone reference)
  Eigen::VectorXd apply_work_; // max(m, 3N), ContactProblem::apply_delassus scratch
  WoodburyNewtonSystem woodbury_;
  SparseNewtonSystem sparse_;
};

} // namespace plantar::contact
