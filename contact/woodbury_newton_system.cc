#include "contact/woodbury_newton_system.h"

#include "contact/dense_lu.h"
#include "contact/tiled_product.h"

namespace plantar::contact {

void WoodburyNewtonSystem::resize(int max_contacts, int rigid_rank) {
  const Eigen::Index size = 3 * static_cast<Eigen::Index>(max_contacts) + rigid_rank;
  max_contacts_ = max_contacts;
  m_ = rigid_rank;
  buffer_.setZero(size * size);
  pivots_.setZero(3 * static_cast<Eigen::Index>(max_contacts) + size);
  z_.setZero(3 * max_contacts, rigid_rank);
  work_.setZero(size);
  rigid_.setZero(max_contacts);
  contacts_.setZero(max_contacts);
  segments_.assign(static_cast<std::size_t>(max_contacts), Segment());
  n_segments_ = n_rigid_ = n_active_ = 0;
}

double WoodburyNewtonSystem::cost(const ContactProblem& problem) {
  const double m = problem.rigid_rank();
  double total = 0.0, in_patches = 0.0;
  for (const CompliantPatch& patch : problem.patches) {
    const double s = patch.n_contacts;
    total += 2.0 / 3.0 * 27.0 * s * s * s + 18.0 * s * s * m + 6.0 * s * m * m + 54.0 * s * s;
    in_patches += s;
  }
  const double k = 3.0 * (problem.n_contacts - in_patches) + m;
  return total + 2.0 / 3.0 * k * k * k;
}

bool WoodburyNewtonSystem::factorize(const ContactProblem& problem, const int* active, int n_active,
                                     const Eigen::MatrixXd& a_blocks,
                                     const Eigen::MatrixXd& b_blocks, double delta) {
  const int m = m_;
  n_active_ = n_active;
  n_segments_ = n_rigid_ = 0;
  // Group the active contacts by patch (patches are sorted, disjoint ranges).
  std::size_t patch = 0;
  for (int i = 0; i < n_active; ++i) {
    const int k = active[i];
    contacts_[i] = k;
    while (patch < problem.patches.size() &&
           k >= problem.patches[patch].first_contact + problem.patches[patch].n_contacts)
      ++patch;
    if (patch < problem.patches.size() && k >= problem.patches[patch].first_contact) {
      if (n_segments_ == 0 || segments_[n_segments_ - 1].patch != static_cast<int>(patch)) {
        segments_[n_segments_++] = Segment{static_cast<int>(patch), i, 0, 0};
      }
      ++segments_[n_segments_ - 1].count;
    } else {
      rigid_[n_rigid_++] = i;
    }
  }
  Eigen::Index offset = 0;
  for (int s = 0; s < n_segments_; ++s) {
    segments_[s].offset = offset;
    offset += 9 * static_cast<Eigen::Index>(segments_[s].count) * segments_[s].count;
  }
  k_offset_ = offset;
  const auto& g = problem.rigid_factor;
  // D_j = A + delta I + B P on the patch's active contacts, its LU, and Z_j = D_j^-1 B G.
  for (int s = 0; s < n_segments_; ++s) {
    const Segment& seg = segments_[s];
    const CompliantPatch& p = problem.patches[static_cast<std::size_t>(seg.patch)];
    const int size = 3 * seg.count;
    Eigen::Map<Eigen::MatrixXd> d(buffer_.data() + seg.offset, size, size);
    for (int i = 0; i < seg.count; ++i) {
      const int ki = contacts_[seg.start + i];
      const Eigen::Matrix3d bi =
          b_blocks.middleCols<3>(3 * ki) * p.node_rotation(ki - p.first_contact);
      for (int l = 0; l < seg.count; ++l) {
        const int kl = contacts_[seg.start + l] - p.first_contact;
        d.block<3, 3>(3 * i, 3 * l).noalias() =
            bi * p.compliance_over_dt.block<3, 3>(3 * (ki - p.first_contact), 3 * kl) *
            p.node_rotation(kl).transpose();
      }
      d.block<3, 3>(3 * i, 3 * i) += a_blocks.middleCols<3>(3 * ki);
      d.diagonal().segment<3>(3 * i).array() += delta;
    }
    auto piv = pivots_.segment(3 * seg.start, size);
    if (!lu_in_place(d, piv))
      return false;
    for (int i = 0; i < seg.count; ++i) {
      const int ki = contacts_[seg.start + i];
      for (int c = 0; c < m; ++c)
        z_.block<3, 1>(3 * (seg.start + i), c).noalias() =
            b_blocks.middleCols<3>(3 * ki) * g.block<3, 1>(3 * ki, c);
    }
    for (int c = 0; c < m; ++c)
      lu_solve_in_place(d, piv, z_.col(c).segment(3 * seg.start, size));
  }
  // K.
  const int kr = 3 * n_rigid_, ks = kr + m;
  Eigen::Map<Eigen::MatrixXd> kmat(buffer_.data() + k_offset_, ks, ks);
  kmat.setZero();
  for (int r = 0; r < n_rigid_; ++r) {
    const int k = contacts_[rigid_[r]];
    kmat.block<3, 3>(3 * r, 3 * r) = a_blocks.middleCols<3>(3 * k);
    kmat.diagonal().segment<3>(3 * r).array() += delta;
    for (int c = 0; c < m; ++c) {
      kmat.block<3, 1>(3 * r, kr + c).noalias() =
          b_blocks.middleCols<3>(3 * k) * g.block<3, 1>(3 * k, c);
      kmat.block<1, 3>(kr + c, 3 * r) = -g.block<3, 1>(3 * k, c).transpose();
    }
  }
  auto k22 = kmat.bottomRightCorner(m, m);
  k22.diagonal().setOnes();
  for (int s = 0; s < n_segments_; ++s) {
    const Segment& seg = segments_[s];
    for (int i = 0; i < seg.count; ++i) { // G_Sj^T Z_j, three rows of G at a time
      const int ki = contacts_[seg.start + i];
      add_product_tiled(k22, g.middleRows<3>(3 * ki).transpose(),
                        z_.middleRows<3>(3 * (seg.start + i)), 1.0);
    }
  }
  return ks == 0 || lu_in_place(kmat, pivots_.segment(3 * max_contacts_, ks));
}

void WoodburyNewtonSystem::solve(const ContactProblem& problem, Eigen::Ref<Eigen::VectorXd> x) {
  const int m = m_, kr = 3 * n_rigid_, ks = kr + m;
  const auto& g = problem.rigid_factor;
  auto rhs = work_.head(ks);
  // t_S = D_S^-1 b_S (in x), rhs = [b_R; G_S^T t_S].
  rhs.tail(m).setZero();
  for (int s = 0; s < n_segments_; ++s) {
    const Segment& seg = segments_[s];
    const int size = 3 * seg.count;
    const Eigen::Map<const Eigen::MatrixXd> d(buffer_.data() + seg.offset, size, size);
    auto t = x.segment(3 * seg.start, size);
    lu_solve_in_place(d, pivots_.segment(3 * seg.start, size), t);
    for (int i = 0; i < seg.count; ++i)
      rhs.tail(m).noalias() +=
          g.middleRows<3>(3 * contacts_[seg.start + i]).transpose() * t.segment<3>(3 * i);
  }
  for (int r = 0; r < n_rigid_; ++r)
    rhs.segment<3>(3 * r) = x.segment<3>(3 * rigid_[r]);
  if (ks > 0) {
    const Eigen::Map<const Eigen::MatrixXd> kmat(buffer_.data() + k_offset_, ks, ks);
    lu_solve_in_place(kmat, pivots_.segment(3 * max_contacts_, ks), rhs);
  }
  // d_S = t_S - Z y, d_R.
  const auto y = rhs.tail(m);
  for (int s = 0; s < n_segments_; ++s) {
    const Segment& seg = segments_[s];
    const int size = 3 * seg.count;
    x.segment(3 * seg.start, size).noalias() -= z_.middleRows(3 * seg.start, size) * y;
  }
  for (int r = 0; r < n_rigid_; ++r)
    x.segment<3>(3 * rigid_[r]) = rhs.segment<3>(3 * r);
}

} // namespace plantar::contact
