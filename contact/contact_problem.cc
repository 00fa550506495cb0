#include "contact/contact_problem.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

namespace plantar::contact {

namespace {
[[noreturn]] void fail(const std::string& what) {
  throw std::invalid_argument("ContactProblem: " + what);
}
} // namespace

void rotate_to_patch(const Eigen::Matrix3d& rotation, Eigen::Ref<Eigen::VectorXd> x) {
  for (Eigen::Index i = 0; i + 2 < x.size(); i += 3) {
    const Eigen::Vector3d y = rotation.transpose() * x.segment<3>(i);
    x.segment<3>(i) = y;
  }
}

void rotate_from_patch(const Eigen::Matrix3d& rotation, Eigen::Ref<Eigen::VectorXd> x) {
  for (Eigen::Index i = 0; i + 2 < x.size(); i += 3) {
    const Eigen::Vector3d y = rotation * x.segment<3>(i);
    x.segment<3>(i) = y;
  }
}

void rotate_to_patch(const CompliantPatch& patch, Eigen::Ref<Eigen::VectorXd> x) {
  if (!patch.per_node_rotations) {
    rotate_to_patch(patch.rotation, x);
    return;
  }
  for (Eigen::Index i = 0; i + 2 < x.size(); i += 3) {
    const Eigen::Vector3d y = patch.node_rotations.middleCols<3>(i).transpose() * x.segment<3>(i);
    x.segment<3>(i) = y;
  }
}

void rotate_from_patch(const CompliantPatch& patch, Eigen::Ref<Eigen::VectorXd> x) {
  if (!patch.per_node_rotations) {
    rotate_from_patch(patch.rotation, x);
    return;
  }
  for (Eigen::Index i = 0; i + 2 < x.size(); i += 3) {
    const Eigen::Vector3d y = patch.node_rotations.middleCols<3>(i) * x.segment<3>(i);
    x.segment<3>(i) = y;
  }
}

void ContactProblem::validate(bool check_matrices) const {
  const int n_max = max_contacts();
  if (n_contacts < 0 || n_contacts > n_max)
    fail("n_contacts = " + std::to_string(n_contacts) +
         " outside [0, max_contacts = " + std::to_string(n_max) + "]");
  if (rigid_factor.rows() != 3 * n_max || free_velocity.size() != 3 * n_max ||
      normal_bias.size() != n_max)
    fail("storage not sized by resize(): rigid_factor rows " + std::to_string(rigid_factor.rows()) +
         ", free_velocity " + std::to_string(free_velocity.size()) + ", normal_bias " +
         std::to_string(normal_bias.size()) + ", expected 3*" + std::to_string(n_max) + ", 3*" +
         std::to_string(n_max) + ", " + std::to_string(n_max));
  for (int k = 0; k < n_contacts; ++k) {
    if (!(friction[k] >= 0.0) || !std::isfinite(friction[k]))
      fail("friction[" + std::to_string(k) + "] = " + std::to_string(friction[k]) +
           ", allowed [0, inf)");
    if (!std::isfinite(normal_bias[k]))
      fail("normal_bias[" + std::to_string(k) + "] is not finite");
    for (int i = 0; i < 3; ++i)
      if (!std::isfinite(free_velocity[3 * k + i]))
        fail("free_velocity[" + std::to_string(3 * k + i) + "] is not finite");
  }
  if (check_matrices && !rigid_factor.topRows(3 * n_contacts).allFinite())
    fail("rigid_factor has non-finite entries");
  if (!general.empty() && general.size() != 3 * n_contacts)
    fail("general Delassus operator has size " + std::to_string(general.size()) +
         ", expected 3 n_contacts = " + std::to_string(3 * n_contacts));
  int previous_end = 0;
  for (std::size_t j = 0; j < patches.size(); ++j) {
    const CompliantPatch& patch = patches[j];
    const std::string name = "patches[" + std::to_string(j) + "]";
    if (patch.first_contact < previous_end || patch.n_contacts < 0 ||
        patch.first_contact + patch.n_contacts > n_contacts)
      fail(name + " range [" + std::to_string(patch.first_contact) + ", " +
           std::to_string(patch.first_contact + patch.n_contacts) +
           ") must be sorted, disjoint and inside [0, n_contacts = " + std::to_string(n_contacts) +
           ")");
    previous_end = patch.first_contact + patch.n_contacts;
    if (patch.compressed != nullptr) {
      if (patch.compressed->n_nodes() != patch.n_contacts || patch.compliance_over_dt.size() != 0)
        fail(name + ".compressed has " + std::to_string(patch.compressed->n_nodes()) +
             " nodes and compliance_over_dt " + std::to_string(patch.compliance_over_dt.size()) +
             " entries, expected n_contacts = " + std::to_string(patch.n_contacts) + " and 0");
      if (!(patch.compressed_scale > 0.0) || !std::isfinite(patch.compressed_scale))
        fail(name + ".compressed_scale = " + std::to_string(patch.compressed_scale) +
             ", allowed (0, inf)");
    } else if (patch.compliance_over_dt.rows() != 3 * patch.n_contacts ||
               patch.compliance_over_dt.cols() != 3 * patch.n_contacts)
      fail(name + ".compliance_over_dt is " + std::to_string(patch.compliance_over_dt.rows()) +
           "x" + std::to_string(patch.compliance_over_dt.cols()) + ", expected " +
           std::to_string(3 * patch.n_contacts) + " square");
    if (check_matrices && !patch.compliance_over_dt.allFinite())
      fail(name + ".compliance_over_dt has non-finite entries");
    const double orthogonality =
        (patch.rotation.transpose() * patch.rotation - Eigen::Matrix3d::Identity())
            .cwiseAbs()
            .maxCoeff();
    if (!(orthogonality <= 1e-10))
      fail(name + ".rotation is not orthonormal (max |R^T R - I| = " +
           std::to_string(orthogonality) + ", allowed <= 1e-10)");
    if (patch.per_node_rotations) {
      if (patch.node_rotations.cols() < 3 * patch.n_contacts)
        fail(name + ".node_rotations has " + std::to_string(patch.node_rotations.cols()) +
             " columns, expected >= 3 n_contacts = " + std::to_string(3 * patch.n_contacts));
      for (int i = 0; i < patch.n_contacts; ++i) {
        const Eigen::Matrix3d a = patch.node_rotation(i);
        const double error =
            (a.transpose() * a - Eigen::Matrix3d::Identity()).cwiseAbs().maxCoeff();
        if (!(error <= 1e-10))
          fail(name + ".node_rotations block " + std::to_string(i) +
               " is not orthonormal (max |a^T a - I| = " + std::to_string(error) +
               ", allowed <= 1e-10)");
      }
    }
    if (patch.warm_product_valid && patch.warm_product.size() < 3 * patch.n_contacts)
      fail(name + ".warm_product has " + std::to_string(patch.warm_product.size()) +
           " entries, expected >= " + std::to_string(3 * patch.n_contacts));
  }
}

Eigen::Matrix3d ContactProblem::diagonal_block(int contact) const {
  double s00 = 0, s01 = 0, s02 = 0, s11 = 0, s12 = 0, s22 = 0;
  for (int c = 0; c < rigid_rank(); ++c) { // G_k G_k^T, the 3 rows of column c adjacent
    const double* g = rigid_factor.col(c).data() + 3 * contact;
    s00 += g[0] * g[0];
    s01 += g[0] * g[1];
    s02 += g[0] * g[2];
    s11 += g[1] * g[1];
    s12 += g[1] * g[2];
    s22 += g[2] * g[2];
  }
  Eigen::Matrix3d block;
  block << s00, s01, s02, s01, s11, s12, s02, s12, s22;
  if (!general.empty())
    block += general.diagonal_block(contact);
  for (const CompliantPatch& patch : patches) {
    const int local = contact - patch.first_contact;
    if (local >= 0 && local < patch.n_contacts) {
      const Eigen::Matrix3d a = patch.node_rotation(local);
      block += a * patch.node_block(local) * a.transpose();
    }
  }
  return block;
}

void ContactProblem::diagonal_traces(Eigen::Ref<Eigen::VectorXd> traces) const {
  const int n = n_contacts;
  if (traces.size() < n)
    fail("diagonal_traces: output has size " + std::to_string(traces.size()) +
         ", needs n_contacts = " + std::to_string(n));
  double* t = traces.data();
  for (int k = 0; k < n; ++k)
    t[k] = 0.0;
  // ||G_k||_F^2 by columns of G (contiguous rows), then the three rows of each contact summed.
  for (int c = 0; c < rigid_rank(); ++c) {
    const double* g = rigid_factor.col(c).data();
    for (int k = 0; k < n; ++k)
      t[k] += g[3 * k] * g[3 * k] + g[3 * k + 1] * g[3 * k + 1] + g[3 * k + 2] * g[3 * k + 2];
  }
  for (const CompliantPatch& patch : patches)
    for (int local = 0; local < patch.n_contacts; ++local)
      t[patch.first_contact + local] += patch.node_block(local).trace();
  if (!general.empty())
    for (int k = 0; k < n; ++k)
      t[k] += general.diagonal_block(k).trace();
}

void ContactProblem::apply_delassus(const Eigen::Ref<const Eigen::VectorXd>& p,
                                    Eigen::Ref<Eigen::VectorXd> rigid_work,
                                    Eigen::Ref<Eigen::VectorXd> out) const {
  const int n3 = 3 * n_contacts;
  const int m = rigid_rank();
  auto g = rigid_factor.topRows(n3);
  rigid_work.head(m).noalias() = g.transpose() * p.head(n3);
  out.head(n3).setZero();
  for (const CompliantPatch& patch : patches) {
    // (I (x) R) C (I (x) R)^T p, by 3-column panels (no scratch).
    const int first = 3 * patch.first_contact, size = 3 * patch.n_contacts;
    auto segment = out.segment(first, size);
    if (patch.compressed != nullptr) {
      patch.compressed->multiply_nodes(
          [&](int node) -> Eigen::Vector3d {
            return patch.node_rotation(node).transpose() * p.segment<3>(first + 3 * node);
          },
          segment, patch.compressed_scale);
      rotate_from_patch(patch, segment);
      continue;
    }
    for (int j = 0; j < size; j += 3) {
      const Eigen::Vector3d p_patch =
          patch.node_rotation(j / 3).transpose() * p.segment<3>(first + j);
      segment.noalias() += patch.compliance_over_dt.middleCols<3>(j) * p_patch;
    }
    rotate_from_patch(patch, segment);
  }
  out.head(n3).noalias() += g * rigid_work.head(m);
  if (!general.empty())
    general.add_product(p, out);
}

void ContactProblem::assemble_delassus(Eigen::MatrixXd& delassus) const {
  delassus.resize(3 * n_contacts, 3 * n_contacts);
  assemble_delassus_into(delassus);
}

void ContactProblem::assemble_delassus_into(Eigen::Ref<Eigen::MatrixXd> out,
                                            bool symmetric_part) const {
  const int n3 = 3 * n_contacts;
  if (out.rows() < n3 || out.cols() < n3)
    fail("assemble_delassus_into: output is " + std::to_string(out.rows()) + "x" +
         std::to_string(out.cols()) + ", needs " + std::to_string(n3) + " square");
  auto g = rigid_factor.topRows(n3);
  auto delassus = out.topLeftCorner(n3, n3);
  delassus.setZero();
  // G G^T by 64-column panels of the product (Eigen's kernels stay under their stack limit).
  for (int j = 0; j < n3; j += 64) {
    const int jb = std::min(64, n3 - j);
    for (int i = 0; i < n3; i += 64) {
      const int ib = std::min(64, n3 - i);
      for (int c = 0; c < g.cols(); c += 64) {
        const int cb = std::min(64, static_cast<int>(g.cols()) - c);
        delassus.block(i, j, ib, jb).noalias() +=
            g.block(i, c, ib, cb) * g.block(j, c, jb, cb).transpose();
      }
    }
  }
  if (!general.empty())
    general.add_to_dense(delassus, symmetric_part);
  for (const CompliantPatch& patch : patches) {
    const int first = 3 * patch.first_contact, size = 3 * patch.n_contacts;
    const Eigen::MatrixXd compressed = // allocates, with a compressed patch only
        patch.compressed != nullptr
            ? Eigen::MatrixXd(patch.compressed_scale * patch.compressed->to_dense())
            : Eigen::MatrixXd();
    const auto& block = patch.compressed != nullptr ? compressed : patch.compliance_over_dt;
    for (int i = 0; i < size; i += 3) {
      const Eigen::Matrix3d a_i = patch.node_rotation(i / 3);
      for (int j = 0; j < size; j += 3)
        delassus.block<3, 3>(first + i, first + j) +=
            a_i * block.block<3, 3>(i, j) * patch.node_rotation(j / 3).transpose();
    }
  }
}

} // namespace plantar::contact
