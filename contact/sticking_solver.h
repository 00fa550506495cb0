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
  /// Sizes the workspace (memory ~ 72 max_contacts^2 bytes for the kept factors).
  void resize(int max_contacts, int rigid_rank);
  /// One attempt from @p impulses (the warm start, in the cones); the result's direct_attempt
  /// says what became of it:
  ///  * accepted: @p impulses hold the solution, the result is final, @p products hold its
  ///    velocity and patch products;
  ///  * refused_cone, refused_residual: @p impulses hold the candidate projected onto the
  ///    cones and @p products.rigid and patch_product its products (StartProducts::held);
  ///  * not_tried, failed: @p impulses unchanged; @p products' rigid, patch_product and
  ///    velocity may have been overwritten.
  /// @p products must be prepared for @p problem.
  SolverResult solve(const ContactProblem& problem, const SolverSettings& settings,
                     Eigen::Ref<Eigen::VectorXd> impulses, DelassusProducts& products);

private:
  // Per patch j, the Cholesky factor of C_AA (its active nodes, in the order of the factor) is
  // kept between solves at rows and columns 3 first_contact and updated node by node.
  bool update_active_factor(const ContactProblem& problem, int j);
  void remove_active_node(int first, int position);
  bool append_active_node(const CompliantPatch& patch, const PatchLever& structure, int node);

  int max_contacts_ = 0;
  int rigid_rank_ = 0;
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
  Eigen::MatrixXd sticking_capacitance_;                  // m x m, Cholesky of I + G^T D_A^-1 G
  Eigen::VectorXd sticking_y_;                            // m
  Eigen::Matrix<double, 6, Eigen::Dynamic> sticking_map_; // 6 x m, lever_gram lever_map
  Eigen::VectorXd g_sliding_;                             // m, G^T p_S of the sliding contacts
};

} // namespace plantar::contact
