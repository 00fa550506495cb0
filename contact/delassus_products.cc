#include "contact/delassus_products.h"

#include "contact/dense_kernels.h"

namespace plantar::contact {

void DelassusProducts::resize(int max_contacts, int rigid_rank) {
  const int n3 = 3 * max_contacts;
  patch_of.setConstant(max_contacts, -1);
  eta.setZero(max_contacts);
  mean_diagonal = 1.0;
  contact_residual.setZero(max_contacts);
  velocity.setZero(n3);
  rigid.setZero(rigid_rank);
  patch_product.setZero(n3);
  warm_change.setZero(n3);
}

void DelassusProducts::prepare(const ContactProblem& problem) {
  const int n = problem.n_contacts;
  patch_of.head(n).setConstant(-1);
  for (std::size_t j = 0; j < problem.patches.size(); ++j) {
    const CompliantPatch& patch = problem.patches[j];
    patch_of.segment(patch.first_contact, patch.n_contacts).setConstant(static_cast<int>(j));
  }
  // The blocks W_kk only for Gauss-Seidel (its local solves); here their traces.
  problem.diagonal_traces(eta);
  double trace_sum = 0.0;
  for (int k = 0; k < n; ++k) {
    const double trace = eta[k];
    eta[k] = trace > 0.0 ? 3.0 / trace : 1.0;
    trace_sum += trace;
  }
  mean_diagonal = (n > 0 && trace_sum > 0.0) ? trace_sum / (3.0 * n) : 1.0;
}

double DelassusProducts::residual(const ContactProblem& problem,
                                  const Eigen::Ref<const Eigen::VectorXd>& p,
                                  const Eigen::Ref<const Eigen::VectorXd>& v) {
  return contact_residuals(problem.n_contacts, p.data(), v.data(), problem.normal_bias.data(),
                           problem.friction.data(), eta.data(), contact_residual.data());
}

void DelassusProducts::compute_velocity(const ContactProblem& problem,
                                        const Eigen::Ref<const Eigen::VectorXd>& p) {
  const int n3 = 3 * problem.n_contacts;
  problem.apply_delassus(p, rigid, velocity);
  velocity.head(n3) += problem.free_velocity.head(n3);
}

void DelassusProducts::compute_patch_product(const CompliantPatch& patch,
                                             const Eigen::Ref<const Eigen::VectorXd>& p) {
  const int first = 3 * patch.first_contact, size = 3 * patch.n_contacts;
  auto out = patch_product.segment(first, size);
  if (patch.compressed != nullptr) {
    patch.compressed->multiply_nodes(
        [&](int node) -> Eigen::Vector3d {
          return patch.node_rotation(node).transpose() * p.segment<3>(first + 3 * node);
        },
        out, patch.compressed_scale);
    return;
  }
  out.setZero();
  for (int j = 0; j < size; j += 3) {
    const Eigen::Vector3d p_patch =
        patch.node_rotation(j / 3).transpose() * p.segment<3>(first + j);
    add_three_columns(patch.compliance_over_dt.col(j).data(),
                      patch.compliance_over_dt.outerStride(), size, p_patch.data(), out.data());
  }
}

void DelassusProducts::add_patch_velocities(const ContactProblem& problem) {
  for (const CompliantPatch& patch : problem.patches) {
    const int first = 3 * patch.first_contact, size = 3 * patch.n_contacts;
    for (int i = first; i < first + size; i += 3)
      velocity.segment<3>(i).noalias() +=
          patch.node_rotation((i - first) / 3) * patch_product.segment<3>(i);
  }
}

} // namespace plantar::contact
