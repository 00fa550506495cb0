#pragma once
// The direct solve on the warm start's active set (SolverSettings::sticking_direct): the
// predictor ContactSolver tries before its iterative solver. Needs every contact on a patch
// with its rigid structure (ContactProblem::patch_levers); the method is described in
// sticking_solver.cc and docs/contact.md.

#include "contact/delassus_products.h"
#include "contact/solver_settings.h"

#include <Eigen/Core>

namespace plantar::contact {

class StickingSolver {
public:
  /// Sizes the workspace (memory ~ 72 max_contacts^2 bytes for the kept factors, plus
  /// ~ 72 max_contacts min(max_contacts, 256) for the sliding contacts' columns).
  void resize(int max_contacts, int rigid_rank);
  /// One attempt from @p impulses (the warm start, in the cones), with up to
  /// settings.sticking_rounds active sets; the result's direct_attempt says what became of it:
  ///  * accepted: @p impulses hold the solution, the result is final, @p products hold its
  ///    velocity and patch products;
  ///  * refused_cone, refused_residual: @p impulses hold the last candidate projected onto the
  ///    cones and @p products.rigid and patch_product its products (StartProducts::held);
  ///  * not_tried, failed: @p impulses unchanged; @p products' rigid, patch_product and
  ///    velocity may have been overwritten.
  /// @p products must be prepared for @p problem.
  SolverResult solve(const ContactProblem& problem, const SolverSettings& settings,
                     Eigen::Ref<Eigen::VectorXd> impulses, DelassusProducts& products);

private:
  // Per patch j, the Cholesky factor of C_AA (its loaded nodes, sticking or sliding, in the
  // order of the factor) is kept between solves at rows and columns 3 first_contact and
  // updated node by node; the sliding nodes sit in its last rows (the tail).
  bool update_active_factor(const ContactProblem& problem, int j);
  void remove_active_node(int first, int position);
  bool append_active_node(const CompliantPatch& patch, const PatchLever& structure, int node);
  // The candidate of the current active set (sticking_solver.cc, steps 1-5): sticking_full_,
  // products.rigid, products.patch_product and products.velocity. Returns the number of
  // contacts outside their cones (a sliding one: p_n < 0), or -1 when S z = r cannot be solved.
  int solve_active_set(const ContactProblem& problem, DelassusProducts& products);

  int max_contacts_ = 0;
  int rigid_rank_ = 0;
  int max_sliding_ = 0;
  Eigen::VectorXd sticking_p_;         // 3N, factor order: x = L^-1 c', then y, then p~_A
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
  Eigen::VectorXi wanted_;     // N: 1 where loaded (p_n > 0): in the factor
  Eigen::VectorXi sliding_;    // N: 1 where loaded and sliding (p_t = mu p_n d): the set S
  Eigen::Matrix2Xd direction_; // 2 x N: d of a sliding contact (contact frame, unit)
  Eigen::MatrixXd sticking_capacitance_;                  // m x m, Cholesky of I + G^T D_A^-1 G
  Eigen::VectorXd sticking_y_;                            // m
  Eigen::Matrix<double, 6, Eigen::Dynamic> sticking_map_; // 6 x m, lever_gram lever_map
  // Sliding contacts g = 0 .. s-1 (patch by patch, in factor order): their tangential (E~,
  // two columns each) and normal (N~) directions through L^-1, on their patch's tail rows.
  Eigen::VectorXi slide_contact_;         // s_max: contact k of g
  Eigen::VectorXi slide_flip_;            // s_max: 1 where g's slip ran along its friction
  Eigen::MatrixXd slide_e_, slide_n_;     // 3N x 2 s_max, 3N x s_max
  Eigen::MatrixXd slide_be_, slide_bn_;   // m x 2 s_max, m x s_max: T^T Z^T E~, T^T Z^T N~
  Eigen::MatrixXd slide_x_;               // m x 2 s_max: S^-1 B_E
  Eigen::MatrixXd slide_gee_, slide_gne_; // 2 s_max x 2 s_max, s_max x 2 s_max
  Eigen::MatrixXd slide_matrix_;          // 2 s_max x 2 s_max: M, then its LU
  Eigen::VectorXi slide_pivots_;          // 3 s_max: of M, then of the Jacobian
  Eigen::MatrixXd slide_jacobian_;        // s_max x s_max: d F / d angles
  Eigen::MatrixXd slide_columns_;         // 2 s_max x s_max: d sigma / d angle
  Eigen::VectorXd slide_f_;               // s_max: F = d^perp . sigma, then the Newton step
  Eigen::VectorXd slide_re_, slide_rn_;   // 4 s_max, s_max: E~^T y0 (then scratch), N~^T y0
  Eigen::VectorXd slide_sigma_;           // 2 s_max: tangential slip velocities, m/s
  Eigen::VectorXd slide_m_;               // m
  int n_sliding_ = 0;
  bool slide_stick_ = false; // a sliding contact slips along its friction: it should stick
};

} // namespace plantar::contact
