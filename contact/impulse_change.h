#pragma once
// The kept state of the Gauss-Seidel iteration following one contact's impulse change.

#include "contact/contact_problem.h"
#include "contact/dense_kernels.h"

#include <Eigen/Core>

namespace plantar::contact {

/// y += G_k^T dp (@p rigid_work, m) and, when contact @p k lies on @p patch (else nullptr),
/// w += C_j (a_k^T dp) over the patch's three columns of k (@p patch_velocity, 3 n_contacts of
/// the solver, patch frames, m/s). @p delta: dp (3, contact frame), N s. O(m + 3 n_j).
inline void add_impulse_change(const ContactProblem& problem, const CompliantPatch* patch, int k,
                               const Eigen::Vector3d& delta, double* rigid_work,
                               double* patch_velocity) {
  for (Eigen::Index c = 0; c < problem.rigid_factor.cols(); ++c) {
    const double* g_c = problem.rigid_factor.col(c).data() + 3 * k;
    rigid_work[c] += g_c[0] * delta[0] + g_c[1] * delta[1] + g_c[2] * delta[2];
  }
  if (patch == nullptr)
    return;
  const Eigen::Vector3d delta_patch =
      patch->node_rotation(k - patch->first_contact).transpose() * delta;
  add_three_columns(patch->compliance_over_dt.col(3 * (k - patch->first_contact)).data(),
                    patch->compliance_over_dt.outerStride(), 3 * patch->n_contacts,
                    delta_patch.data(), patch_velocity + 3 * patch->first_contact);
}

} // namespace plantar::contact
