#pragma once
// Solver of the frictional contact problem of contact_problem.h.
//
// Two methods share one workspace, sized once for max_contacts:
//  * Gauss-Seidel (baseline): sweeps over contacts, each contact's 3x3 problem
//    solved exactly (local_contact_solve.h) with the others fixed; the
//    velocity is kept up to date through y = G^T p (rank m) and the patch
//    blocks, so a sweep costs O(n m + sum_j n_j^2).
//  * ADMM (Carpentier et al. 2024; Tasora et al. 2021): with De Saxce's
//    correction s(v) = mu ||v_t|| e_n fixed per iteration, split p = x (free)
//    = z (in the cones), scaled dual u:
//      (W + (rho + eta) I) x = -(v_free + b e_n + s) + (rho + eta) z - rho u
//      z = P_K(x + u),  u = u + x - z,
//    rho adapted from the ratio of primal ||x - z|| and dual ||z - z_prev||
//    residuals. The matrix is factorised with the low-rank structure
//    (Woodbury): D = blockdiag(C_j/dt^2) + c I (patch blocks by Cholesky,
//    rigid-only contacts scalar), S = I_m + G^T D^-1 G (Cholesky, m x m).
// Both report the natural-map residual max_k || p_k - P_K(p_k - eta_k vt_k) || / eta_k
// (m/s), with vt the De Saxce velocity and eta_k = 3 / trace(W_kk).
//
// solve() allocates nothing once resize() was called with max_contacts >=
// n_contacts and the problem's rigid rank (tested with Eigen's malloc guard up
// to 250 contacts in one patch): the patch Cholesky factorisations use an
// in-place tiled algorithm whose Eigen kernel calls stay under Eigen's stack
// scratch limit. A patch factor is reused by
// the next solve when the patch block and the shift rho + eta are unchanged
// (with warm_rho the next solve starts at the last rho), so in a time loop
// with constant dt and contact set the O(n^3) factorisation is rare.

#include "contact/contact_problem.h"
#include "contact/solver_settings.h"

#include <Eigen/Core>

namespace plantar::contact {

class ContactSolver {
public:
  ContactSolver() = default;
  ContactSolver(int max_contacts, int rigid_rank) { resize(max_contacts, rigid_rank); }

  /// Sizes every workspace (memory ~ 72 max_contacts^2 bytes for ADMM's factor).
  void resize(int max_contacts, int rigid_rank);
  int max_contacts() const { return max_contacts_; }

  /// Solves @p problem. @param impulses (>= 3 n_contacts), N s: warm start on
  /// input (if settings.warm_start), solution on output (always in the cones).
  /// Throws std::invalid_argument on bad settings or a problem larger than the
  /// workspace; numerical trouble is reported in the result's status.
  SolverResult solve(const ContactProblem& problem, const SolverSettings& settings,
                     Eigen::Ref<Eigen::VectorXd> impulses);

  /// Contact velocities v = W p + v_free of the last solve (3 n_contacts), m/s.
  Eigen::Ref<const Eigen::VectorXd> velocity(int n_contacts) const {
    return velocity_.head(3 * n_contacts);
  }

  /// C_j/dt^2 (I (x) R_j)^T p of the last solve's impulses for @p patch (3 n_contacts of the
  /// patch, m/s, patch frame): pass it back as CompliantPatch::warm_product when the next
  /// solve starts from the same patch-frame impulses (saves one pass over the block).
  Eigen::Ref<const Eigen::VectorXd> patch_product(const CompliantPatch& patch) const {
    return patch_velocity_.segment(3 * patch.first_contact, 3 * patch.n_contacts);
  }

  /// Patch Cholesky factorisations done since resize() (ADMM; reused ones not counted).
  long n_patch_factorizations() const { return n_patch_factorizations_; }

  /// Keep the residual of every iteration of the next solves (up to
  /// @p capacity iterations; 0 turns it off). Allocates; for benchmarks.
  void record_history(int capacity) { history_.setZero(capacity); }
  /// Residuals (m/s) of iterations 1..n of the last solve, n = min(iterations, capacity).
  Eigen::Ref<const Eigen::VectorXd> history() const { return history_.head(history_size_); }

  /// Natural-map residual (m/s, max over contacts) of @p impulses with the
  /// velocities @p velocity = W p + v_free, using this solver's eta_k (call
  /// after solve() on the same problem, or use the static overload).
  static double complementarity_residual(const ContactProblem& problem,
                                         const Eigen::Ref<const Eigen::VectorXd>& impulses,
                                         const Eigen::Ref<const Eigen::VectorXd>& velocity);

private:
  void prepare(const ContactProblem& problem);
  // max_k of the natural-map residuals, each kept in contact_residual_ (dense_kernels.h).
  double residual(const ContactProblem& problem, const Eigen::Ref<const Eigen::VectorXd>& p,
                  const Eigen::Ref<const Eigen::VectorXd>& v);
  void compute_velocity(const ContactProblem& problem, const Eigen::Ref<const Eigen::VectorXd>& p);
  // patch_velocity_[patch rows] = C (I (x) R)^T p (one pass over the block).
  void compute_patch_product(const CompliantPatch& patch,
                             const Eigen::Ref<const Eigen::VectorXd>& p);
  // velocity_[patch rows] += (I (x) R) patch_velocity_[patch rows], every patch.
  void add_patch_velocities(const ContactProblem& problem);
  // rigid_work_ = G^T p and patch_velocity_ (the patch products) of the warm start @p p, for
  // the iteration (start_ready_ = true).
  void start_iteration(const ContactProblem& problem, const Eigen::Ref<const Eigen::VectorXd>& p);
  SolverResult solve_gauss_seidel(const ContactProblem& problem, const SolverSettings& settings,
                                  Eigen::Ref<Eigen::VectorXd> impulses);
  SolverResult solve_admm(const ContactProblem& problem, const SolverSettings& settings,
                          Eigen::Ref<Eigen::VectorXd> impulses);
  // The direct solve on the warm start's active set (contact_solver_sticking.cc): true when
  // it was used (impulses, velocity_, patch_velocity_, result filled).
  bool solve_sticking(const ContactProblem& problem, const SolverSettings& settings,
                      Eigen::Ref<Eigen::VectorXd> impulses, SolverResult& result);
  bool factorize(const ContactProblem& problem, double shift);
  void solve_shifted(const ContactProblem& problem, const Eigen::Ref<const Eigen::VectorXd>& rhs,
                     Eigen::Ref<Eigen::VectorXd> x);

  int max_contacts_ = 0;
  int rigid_rank_ = 0;
  // Shared.
  Eigen::VectorXd velocity_;         // W p + v_free (3N)
  Eigen::VectorXd rigid_work_;       // m
  Eigen::MatrixXd diag_blocks_;      // 3 x 3N, W_kk (by solve_gauss_seidel, at first need)
  Eigen::MatrixXd diag_inverses_;    // 3 x 3N, W_kk^-1 where has_inverse_ is 1 (local_inverse)
  Eigen::VectorXi has_inverse_;      // N: 1, 0 (singular), or -1 (W_kk not built in this call)
  Eigen::VectorXd eta_;              // N, 3 / trace(W_kk)
  Eigen::VectorXd contact_residual_; // N, each contact's residual of the last residual() call
  Eigen::VectorXi patch_of_;         // N, patch index or -1
  double mean_diagonal_ = 1.0;
  // Gauss-Seidel.
  Eigen::VectorXd patch_velocity_;    // C_j/dt^2 (I (x) R_j)^T p per patch, patch frames (3N)
  Eigen::VectorXd projection_change_; // warm start projected onto the cones minus given (3N)
  bool warm_products_usable_ = false; // settings.warm_start of this solve
  // Direct solve on the warm start's active set (contact_solver_sticking.cc). Per patch j,
  // the Cholesky factor of C_AA (its active nodes, in the order of the factor) is kept
  // between solves at rows and columns 3 first_contact and updated node by node.
  bool update_active_factor(const ContactProblem& problem, int j);
  void remove_active_node(int first, int position);
  bool append_active_node(const CompliantPatch& patch, const PatchLever& structure, int node);
  Eigen::VectorXd sticking_p_;         // 3N, factor order: x = L^-1 c', then p~_A
  Eigen::VectorXd sticking_c_;         // 3N, factor order: c~ = (I (x) R)^T (v_free + b e_n)
  Eigen::VectorXd sticking_full_;      // 3N, candidate impulses (contact frames)
  Eigen::VectorXd sticking_work_;      // 3N, rank-1 update vector
  Eigen::MatrixXd sticking_columns_;   // 3N x 3, an appended node's columns
  Eigen::MatrixXd active_factor_;      // 3N x 3N, L of C_AA per patch
  Eigen::MatrixXd active_lever_solve_; // 3N x 6, Z = L^-1 Lambda_A (factor order)
  Eigen::MatrixXd active_gram_;        // 6 x 6N, Z^T Z = Lambda_A^T C_AA^-1 Lambda_A at 6 first
  Eigen::VectorXi active_order_;       // N: at first + i, the local node of position i
  Eigen::VectorXi active_position_;    // N: position of contact k in its patch's factor, -1
  Eigen::VectorXi active_owner_;       // N: patch whose factor occupies contact k's rows
  Eigen::Matrix<long, Eigen::Dynamic, 1> active_version_; // per patch: PatchLever::version
  Eigen::VectorXi active_first_, active_size_, active_count_, active_updates_; // per patch
  Eigen::VectorXi wanted_;  // N: 1 where the warm start sticks (p_n > 0, inside the cone)
  Eigen::VectorXi sliding_; // N: 1 where it slides (p_n > 0, on the cone): held in the solve
  // rigid_work_ = G^T p and patch_velocity_ hold the iteration's start (start_iteration(), or
  // the direct solve's refused candidate); cleared when solve_sticking uses them.
  bool start_ready_ = false;
  Eigen::MatrixXd sticking_capacitance_;                  // m x m, Cholesky of I + G^T D_A^-1 G
  Eigen::VectorXd sticking_y_;                            // m
  Eigen::Matrix<double, 6, Eigen::Dynamic> sticking_map_; // 6 x m, lever_gram lever_map
  // ADMM.
  Eigen::VectorXd x_, z_, z_prev_, dual_, rhs_, tmp_; // 3N each
  Eigen::MatrixXd patch_factor_;                      // 3N x 3N, Cholesky of patch blocks + cI
  Eigen::MatrixXd low_rank_;                          // 3N x m, H = D^-1 G
  Eigen::MatrixXd capacitance_;                       // m x m, Cholesky of I + G^T H
  Eigen::VectorXd rigid_work2_;                       // m
  Eigen::VectorXd de_saxce_;                          // N, frozen mu ||v_t||
  double shift_ = 0.0;
  Eigen::MatrixXd patch_copy_;   // 3N x 3N, patch blocks of the last factorisation
  Eigen::VectorXi cached_first_; // per patch: first row and size of the cached factor
  Eigen::VectorXi cached_size_;
  int n_cached_patches_ = -1;
  double cached_shift_ = -1.0;
  double last_rho_ = 0.0;   // final rho of the last ADMM solve (warm rho)
  Eigen::VectorXd history_; // optional residual per iteration
  int history_size_ = 0;
  long n_patch_factorizations_ = 0;
  void record(int iteration, double value) {
    if (iteration <= history_.size()) {
      history_[iteration - 1] = value;
      history_size_ = iteration;
    }
  }
};

} // namespace plantar::contact
