#pragma once
// What the contact solvers of one solve share (sized once for max_contacts): the scales of W
// of the problem, and the products of the current impulses p that an iteration starts from
// and that the facade returns (ContactSolver::velocity, patch_product).

#include "contact/contact_problem.h"

#include <Eigen/Core>

namespace plantar::contact {

struct DelassusProducts {
  /// Sizes every vector for @p max_contacts contacts and rigid rank @p rigid_rank.
  void resize(int max_contacts, int rigid_rank);
  /// patch_of, eta and mean_diagonal of @p problem (one pass over G).
  void prepare(const ContactProblem& problem);
  /// max_k of the natural-map residuals of @p p with velocities @p v, each kept in
  /// contact_residual (dense_kernels.h).
  double residual(const ContactProblem& problem, const Eigen::Ref<const Eigen::VectorXd>& p,
                  const Eigen::Ref<const Eigen::VectorXd>& v);
  /// velocity = W p + v_free (rigid = G^T p on the way).
  void compute_velocity(const ContactProblem& problem, const Eigen::Ref<const Eigen::VectorXd>& p);
  /// patch_product[patch rows] = C A^T p, A = blockdiag(a_i) (one pass over the block).
  void compute_patch_product(const CompliantPatch& patch,
                             const Eigen::Ref<const Eigen::VectorXd>& p);
  /// velocity[patch rows] += A patch_product[patch rows], every patch.
  void add_patch_velocities(const ContactProblem& problem);

  // Scales of W (prepare()).
  Eigen::VectorXi patch_of;         // N, patch index or -1
  Eigen::VectorXd eta;              // N, 3 / trace(W_kk)
  double mean_diagonal = 1.0;       // trace(W) / 3n
  Eigen::VectorXd contact_residual; // N, each contact's residual of the last residual() call
  // Products of the current impulses p.
  Eigen::VectorXd velocity;      // 3N, W p + v_free, m/s
  Eigen::VectorXd rigid;         // m, y = G^T p
  Eigen::VectorXd patch_product; // 3N, C_j/dt^2 A_j^T p per patch, patch frames, m/s
  // The cone projection's change of the caller's warm start (3N; NaN for a non-finite
  // impulse): corrects CompliantPatch::warm_product, the product of the unprojected impulses.
  Eigen::VectorXd warm_change;
};

} // namespace plantar::contact
