// Direct solve on the warm start's active set (part of ContactSolver,
// SolverSettings::sticking_direct).
//
// The warm start predicts, per contact, sticking (p_n > 0, strictly inside the cone) or
// separated (p = 0). With p_I = 0 on the separated set, sticking contacts have zero De Saxce
// velocity: W_AA p_A = -c_A, c_k = v_free,k + b_k e_n. With every contact on a patch whose
// rigid rows are G_j = (I (x) R_j) Lambda_j T_j (CompliantPatch::lever, lever_map) and
// D_A = blockdiag((I (x) R_j) C_j,AA (I (x) R_j)^T), C_j = C/dt^2 in the patch frame,
// Woodbury gives, in patch frames (c~ = (I (x) R_j)^T c):
//   x_j = C_j,AA^-1 c~_j,A                              (two triangular solves)
//   S z = sum_j T_j^T Lambda_j,A^T x_j,   S = I_m + sum_j T_j^T (Lambda_A^T C_AA^-1 Lambda_A) T_j
//   p~_j,A = -(x_j - (C_j,AA^-1 Lambda_j,A) T_j z)
// The candidate is kept when every p_A lies in its cone and the natural-map residual of all
// contacts (the separated ones need v_n + b >= 0) meets the tolerance; it is then a solution
// of the contact problem. Otherwise the iterative solver runs from the warm start.
//
// The factor L of C_j,AA is kept between solves and updated node by node when A changes:
// removing a node is a rank-3 update of the trailing factor, adding one a triangular solve
// (O(|A|^2) each instead of O(|A|^3)); it is rebuilt from scratch after 60 updates.
#include "coupling/contact/contact_solver.h"

#include "coupling/contact/dense_kernels.h"

#include <Eigen/Cholesky>
#include <cmath>

namespace plantar::coupling {

namespace {
using Vector6 = Eigen::Matrix<double, 6, 1>;
constexpr int kMaxUpdates = 60;   // factor updates before a rebuild (round-off)
constexpr int kRetryInterval = 8; // solves between retries of a refused prediction
} // namespace

void ContactSolver::remove_active_node(int first, int position) {
  // L = [L11 0 0; L21 L22 0; L31 L32 L33] with the node's block in the middle: the factor
  // without it is [L11 0; L31 L33'] with L33' L33'^T = L33 L33^T + L32 L32^T.
  const int base = 3 * first;
  const int count = active_count_[active_owner_[first]];
  const int size = 3 * count;
  const int r = 3 * position;
  const int k = size - r - 3;
  auto l = active_factor_.block(base, base, size, size);
  for (int c = 0; c < 3; ++c) { // three rank-1 updates of L33
    auto x = sticking_work_.head(k);
    x = l.block(r + 3, r + c, k, 1);
    for (int i = 0; i < k; ++i) {
      const double lii = l(r + 3 + i, r + 3 + i);
      const double rho = std::sqrt(lii * lii + x[i] * x[i]);
      const double cs = rho / lii, sn = x[i] / lii;
      l(r + 3 + i, r + 3 + i) = rho;
      for (int t = i + 1; t < k; ++t) {
        const double li = (l(r + 3 + t, r + 3 + i) + sn * x[t]) / cs;
        x[t] = cs * x[t] - sn * li;
        l(r + 3 + t, r + 3 + i) = li;
      }
    }
  }
  // Shift the rows below the node up by 3 (columns before it), then L33' up and left by 3.
  for (int col = 0; col < r; ++col)
    for (int row = r; row < size - 3; ++row)
      l(row, col) = l(row + 3, col);
  for (int col = 0; col < k; ++col)
    for (int row = col; row < k; ++row)
      l(r + row, r + col) = l(r + 3 + row, r + 3 + col);
  for (int i = position; i + 1 < count; ++i) {
    active_order_[first + i] = active_order_[first + i + 1];
    active_position_[first + active_order_[first + i]] = i;
  }
}

bool ContactSolver::append_active_node(const CompliantPatch& patch, int node) {
  // New rows [B^T L^-T, chol(C_nn - B^T C_AA^-1 B)], B = C_A,n (3 |A| x 3).
  const int first = patch.first_contact;
  const int base = 3 * first;
  int& count = active_count_[active_owner_[first]];
  const int size = 3 * count;
  auto l = active_factor_.block(base, base, size + 3, size + 3);
  auto b = sticking_columns_.topRows(size);
  for (int i = 0; i < count; ++i)
    b.middleRows<3>(3 * i) =
        patch.compliance_over_dt.block<3, 3>(3 * active_order_[first + i], 3 * node);
  for (int c = 0; c < 3; ++c) {
    auto column = b.col(c);
    l.topLeftCorner(size, size).triangularView<Eigen::Lower>().solveInPlace(column);
  }
  l.block(size, 0, 3, size) = b.transpose();
  Eigen::Matrix3d d = patch.compliance_over_dt.block<3, 3>(3 * node, 3 * node);
  d.noalias() -= b.transpose() * b;
  for (int j = 0; j < 3; ++j) { // 3 x 3 Cholesky
    double djj = d(j, j);
    for (int t = 0; t < j; ++t)
      djj -= d(j, t) * d(j, t);
    if (!(djj > 0.0))
      return false;
    d(j, j) = std::sqrt(djj);
    for (int i = j + 1; i < 3; ++i) {
      double dij = d(i, j);
      for (int t = 0; t < j; ++t)
        dij -= d(i, t) * d(j, t);
      d(i, j) = dij / d(j, j);
    }
  }
  l.block<3, 3>(size, size) = d.triangularView<Eigen::Lower>();
  active_order_[first + count] = node;
  active_position_[first + node] = count;
  ++count;
  return true;
}

bool ContactSolver::update_active_factor(const ContactProblem& problem, int j) {
  const CompliantPatch& patch = problem.patches[j];
  const int first = patch.first_contact, n_nodes = patch.n_contacts;
  bool owned = active_version_[j] == patch.sticking_version && active_first_[j] == first &&
               active_size_[j] == n_nodes;
  for (int k = first; owned && k < first + n_nodes; ++k)
    owned = active_owner_[k] == j;
  bool changed = false;
  if (!owned || active_updates_[j] >= kMaxUpdates) { // start from an empty factor
    active_version_[j] = patch.sticking_version;
    active_first_[j] = first;
    active_size_[j] = n_nodes;
    active_count_[j] = 0;
    active_updates_[j] = 0;
    active_owner_.segment(first, n_nodes).setConstant(j);
    active_position_.segment(first, n_nodes).setConstant(-1);
    changed = true;
  }
  const bool rebuilding = active_count_[j] == 0;
  for (int i = active_count_[j] - 1; i >= 0; --i) {
    const int node = active_order_[first + i];
    if (!wanted_[first + node]) {
      remove_active_node(first, i);
      active_position_[first + node] = -1;
      --active_count_[j];
      ++active_updates_[j];
      changed = true;
    }
  }
  for (int node = 0; node < n_nodes; ++node) {
    if (wanted_[first + node] && active_position_[first + node] < 0) {
      if (!append_active_node(patch, node)) {
        active_version_[j] = -1; // not positive definite: start again next time
        return false;
      }
      active_updates_[j] += rebuilding ? 0 : 1;
      changed = true;
    }
  }
  if (changed && active_count_[j] > 0) { // C_AA^-1 Lambda_A and Lambda_A^T C_AA^-1 Lambda_A
    const int size = 3 * active_count_[j];
    auto y = active_lever_solve_.middleRows(3 * first, size);
    for (int i = 0; i < active_count_[j]; ++i)
      y.middleRows<3>(3 * i) = patch.lever.middleRows<3>(3 * active_order_[first + i]);
    const auto l = active_factor_.block(3 * first, 3 * first, size, size);
    for (int c = 0; c < 6; ++c) { // Z = L^-1 Lambda_A
      auto column = y.col(c);
      l.triangularView<Eigen::Lower>().solveInPlace(column);
    }
    active_gram_.middleCols<6>(6 * first).noalias() = y.transpose() * y; // Z^T Z
    for (int c = 0; c < 6; ++c) {                                        // Y = L^-T Z
      auto column = y.col(c);
      l.triangularView<Eigen::Lower>().transpose().solveInPlace(column);
    }
  }
  return true;
}

bool ContactSolver::solve_sticking(const ContactProblem& problem, const SolverSettings& settings,
                                   Eigen::Ref<Eigen::VectorXd> impulses, SolverResult& result) {
  const int n = problem.n_contacts;
  const int n3 = 3 * n;
  const int m = rigid_rank_;
  if (static_cast<int>(problem.patches.size()) > max_contacts_)
    return false;
  int covered = 0;
  for (const CompliantPatch& patch : problem.patches) {
    if (patch.n_contacts == 0)
      continue;
    if (patch.sticking_version <= 0 || !patch.lever_map_valid ||
        patch.lever.rows() != 3 * patch.n_contacts || patch.lever_map.rows() != 6 ||
        patch.lever_map.cols() != m)
      return false;
    covered += patch.n_contacts;
  }
  if (covered != n)
    return false; // a contact without compliance: D singular
  int n_active = 0;
  for (int k = 0; k < n; ++k) { // the warm start's prediction: sticking or separated
    const double p_n = impulses[3 * k];
    const double t2 =
        impulses[3 * k + 1] * impulses[3 * k + 1] + impulses[3 * k + 2] * impulses[3 * k + 2];
    const double mu = problem.friction[k];
    wanted_[k] = p_n > 0.0 ? 1 : 0;
    if (p_n > 0.0 && !(t2 < mu * mu * p_n * p_n))
      return false; // predicted sliding
    n_active += wanted_[k];
  }
  if (n_active == 0)
    return false;
  // A candidate refused on this prediction is usually refused again while the prediction
  // stays (e.g. edge nodes slipping): retry it only every kRetryInterval solves.
  bool same_prediction = refused_size_ == n;
  for (int k = 0; same_prediction && k < n; ++k)
    same_prediction = refused_wanted_[k] == wanted_[k];
  if (same_prediction && ++refused_skips_ < kRetryInterval)
    return false;
  refused_skips_ = 0;
  refused_size_ = n; // until accepted
  refused_wanted_.head(n) = wanted_.head(n);

  // x_j = C_j,AA^-1 c~_j,A; S and G^T D_A^-1 c.
  sticking_capacitance_.setIdentity();
  sticking_y_.setZero();
  for (std::size_t j = 0; j < problem.patches.size(); ++j) {
    const CompliantPatch& patch = problem.patches[j];
    if (patch.n_contacts == 0)
      continue;
    if (!update_active_factor(problem, static_cast<int>(j)))
      return false;
    const int first = patch.first_contact, count = active_count_[j];
    if (count == 0)
      continue;
    auto c = sticking_c_.segment(3 * first, 3 * count);
    auto x = sticking_p_.segment(3 * first, 3 * count);
    for (int i = 0; i < count; ++i) {
      const int k = first + active_order_[first + i];
      Eigen::Vector3d c_k = problem.free_velocity.segment<3>(3 * k);
      c_k[0] += problem.normal_bias[k];
      c.segment<3>(3 * i).noalias() = patch.rotation.transpose() * c_k;
    }
    x = c;
    const auto l = active_factor_.block(3 * first, 3 * first, 3 * count, 3 * count)
                       .triangularView<Eigen::Lower>();
    l.solveInPlace(x);
    l.transpose().solveInPlace(x);
    Vector6 t = Vector6::Zero();
    for (int i = 0; i < count; ++i)
      t.noalias() +=
          patch.lever.middleRows<3>(3 * active_order_[first + i]).transpose() * x.segment<3>(3 * i);
    sticking_y_.noalias() += patch.lever_map.transpose() * t;
    sticking_map_.noalias() = active_gram_.middleCols<6>(6 * first) * patch.lever_map;
    sticking_capacitance_.noalias() += patch.lever_map.transpose() * sticking_map_;
  }
  if (Eigen::internal::llt_inplace<double, Eigen::Lower>::unblocked(sticking_capacitance_) >= 0)
    return false;
  auto s = sticking_capacitance_.triangularView<Eigen::Lower>();
  s.solveInPlace(sticking_y_);
  s.transpose().solveInPlace(sticking_y_); // z

  // p~_A = -(x - Y_A T z); G^T p; cone check; candidate in contact frames.
  rigid_work_.head(m).setZero();
  sticking_full_.head(n3).setZero();
  for (std::size_t j = 0; j < problem.patches.size(); ++j) {
    const CompliantPatch& patch = problem.patches[j];
    const int first = patch.first_contact, count = patch.n_contacts > 0 ? active_count_[j] : 0;
    if (count == 0)
      continue;
    auto x = sticking_p_.segment(3 * first, 3 * count);
    const Vector6 u = patch.lever_map * sticking_y_;
    x.noalias() -= active_lever_solve_.middleRows(3 * first, 3 * count) * u;
    x = -x;
    Vector6 t = Vector6::Zero();
    for (int i = 0; i < count; ++i) {
      const int node = active_order_[first + i];
      t.noalias() += patch.lever.middleRows<3>(3 * node).transpose() * x.segment<3>(3 * i);
      const Eigen::Vector3d p = patch.rotation * x.segment<3>(3 * i);
      const double mu = problem.friction[first + node];
      if (!(p[0] >= 0.0) || !(p[1] * p[1] + p[2] * p[2] <= mu * mu * p[0] * p[0]))
        return false;
      sticking_full_.segment<3>(3 * (first + node)) = p;
    }
    rigid_work_.head(m).noalias() += patch.lever_map.transpose() * t;
  }

  // Patch products C_j (I (x) R)^T p (patch frame): for a full active set from the sticking
  // equations, C p~ = -(c~ + Lambda T G^T p); otherwise by the active columns.
  for (std::size_t j = 0; j < problem.patches.size(); ++j) {
    const CompliantPatch& patch = problem.patches[j];
    if (patch.n_contacts == 0)
      continue;
    const int first = patch.first_contact, count = active_count_[j];
    const int size = 3 * patch.n_contacts;
    auto w = patch_velocity_.segment(3 * first, size);
    if (count == patch.n_contacts) {
      const Vector6 v6 = patch.lever_map * rigid_work_.head(m);
      for (int i = 0; i < count; ++i) {
        const int node = active_order_[first + i];
        w.segment<3>(3 * node).noalias() =
            -(sticking_c_.segment<3>(3 * (first + i)) + patch.lever.middleRows<3>(3 * node) * v6);
      }
    } else {
      w.setZero();
      for (int i = 0; i < count; ++i) {
        const int node = active_order_[first + i];
        add_three_columns(patch.compliance_over_dt.col(3 * node).data(),
                          patch.compliance_over_dt.outerStride(), size,
                          sticking_p_.data() + 3 * (first + i), w.data());
      }
    }
  }
  velocity_.head(n3).noalias() = problem.rigid_factor.topRows(n3) * rigid_work_.head(m);
  velocity_.head(n3) += problem.free_velocity.head(n3);
  add_patch_velocities(problem);
  const double r = residual(problem, sticking_full_, velocity_);
  if (!(r <= settings.tolerance))
    return false; // a separated contact closes, or round-off: iterate from the warm start
  impulses.head(n3) = sticking_full_.head(n3);
  refused_size_ = -1;
  result = SolverResult{};
  result.direct = true;
  result.iterations = 0;
  result.residual = r;
  result.status = SolverStatus::converged;
  return true;
}

} // namespace plantar::coupling
