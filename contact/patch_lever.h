#pragma once
// The rigid structure of a compliant patch whose nodes are fixed to one rigid body: the
// input of the direct solve on the warm start's active set (sticking_solver.h), held by
// ContactProblem::patch_levers, parallel to ContactProblem::patches.

#include <Eigen/Core>

namespace plantar::contact {

/// The patch's rows of G factored as
///   G_patch = (I (x) R) lever lever_map,
/// R the patch's rotation (CompliantPatch::rotation).
struct PatchLever {
  /// (3 n_contacts x 6, patch frame, constant): node i's rows [I, -[rho_i]x] for its position
  /// rho_i (rigid_lever()).
  Eigen::MatrixXd lever;
  /// (6 x m), set per step by the owner, with lever_map_valid.
  Eigen::MatrixXd lever_map;
  bool lever_map_valid = false;
  /// Set by set_sticking_structure(), 0 before: identifies the (block, lever) pair, so that
  /// the solver knows when the factors it keeps for this patch are stale.
  long version = 0;
};

/// Lambda (3 n x 6) for nodes fixed to one rigid body: node k's rows [I, -[rho_k]x], rho_k
/// the k-th column of @p nodes (3 x n, m, body frame), so that Lambda (v_o, w) gives the node
/// velocities v_o + w x rho_k. Allocates.
Eigen::MatrixXd rigid_lever(const Eigen::Matrix3Xd& nodes);

/// Stores @p lever (3 n x 6, see PatchLever::lever) in @p patch_lever and gives it a new
/// version. Call it after every change of the patch's compliance_over_dt (the solver's factors
/// of the block are then rebuilt). Allocates when the size changes.
void set_sticking_structure(PatchLever& patch_lever,
                            const Eigen::Ref<const Eigen::MatrixXd>& lever);

} // namespace plantar::contact
