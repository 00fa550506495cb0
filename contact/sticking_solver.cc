// Direct solve on the warm start's active set (StickingSolver, sticking_solver.h).
//
// The warm start predicts, per contact, sticking (p_n > 0, inside the cone by more than a
// relative 1e-9), sliding (p_n > 0 on the cone: S, held at its warm-start impulse) or
// separated (p = 0).
// Sticking contacts then have zero De Saxce velocity: W_AA p_A = -c'_A with
// c' = v_free + b e_n + W_AS p_S. With every contact on a patch whose rigid rows are
// G_j = (I (x) R_j) Lambda_j T_j (ContactProblem::patch_levers: lever, lever_map) and
// D_A = blockdiag((I (x) R_j) C_j,AA (I (x) R_j)^T), C_j = C/dt^2 in the patch frame,
// Woodbury gives, in patch frames, with L L^T = C_j,AA and Z = L^-1 Lambda_j,A:
//   x_j = L^-1 c~'_j,A                                   (one triangular solve)
//   S z = sum_j T_j^T Z^T x_j,   S = I_m + sum_j T_j^T (Z^T Z) T_j
//   p~_j,A = -L^-T (x_j - Z T_j z)                      (one triangular solve)
// The candidate is kept when every p_A lies in its cone and the natural-map residual of all
// contacts (the separated ones need v_n + b >= 0) meets the tolerance; it is then a solution
// of the contact problem. Otherwise it is projected onto the cones and the iterative solver
// starts from it (with its G^T p and patch products), not from the warm start.
//
// L, Z and Z^T Z are kept between solves and updated node by node when A changes: adding a
// node is a triangular solve for its rows of L and Z (O(|A|^2)); removing one is a rank-3
// update of the trailing factor whose rotations also update Z and Z^T Z (O(|A|^2)); the
// factor is rebuilt from scratch after 60 updates.
#include "contact/sticking_solver.h"

#include "contact/coulomb_cone.h"
#include "contact/dense_kernels.h"
#include "contact/impulse_change.h"

#include <Eigen/Cholesky>
#include <cmath>

namespace plantar::contact {

namespace {
using Vector6 = Eigen::Matrix<double, 6, 1>;
constexpr int kMaxUpdates = 60; // factor updates before a rebuild (round-off)

// Lambda_i u: rows 3 i .. 3 i + 2 of lever (3n x 6, column-major) times u (6).
inline Eigen::Vector3d lever_times(const Eigen::MatrixXd& lever, int node, const Vector6& u) {
  const double* l = lever.data() + 3 * node;
  const Eigen::Index ld = lever.outerStride();
  Eigen::Vector3d out = Eigen::Vector3d::Zero();
  for (int c = 0; c < 6; ++c, l += ld) {
    out[0] += l[0] * u[c];
    out[1] += l[1] * u[c];
    out[2] += l[2] * u[c];
  }
  return out;
}

// t += Lambda_i^T x (x: 3).
inline void add_lever_transposed(const Eigen::MatrixXd& lever, int node, const Eigen::Vector3d& x,
                                 Vector6& t) {
  const double* l = lever.data() + 3 * node;
  const Eigen::Index ld = lever.outerStride();
  for (int c = 0; c < 6; ++c, l += ld)
    t[c] += l[0] * x[0] + l[1] * x[1] + l[2] * x[2];
}
} // namespace

void StickingSolver::remove_active_node(int first, int position) {
  // L = [L11 0 0; L21 L22 0; L31 L32 L33] with the node's block in the middle: the factor
  // without it is [L11 0; L31 L33'] with L33' L33'^T = L33 L33^T + L32 L32^T.
  const int base = 3 * first;
  const int count = active_count_[active_owner_[first]];
  const int size = 3 * count;
  const int r = 3 * position;
  const int k = size - r - 3;
  auto l = active_factor_.block(base, base, size, size);
  // Z = L^-1 Lambda_A follows: L33' Z3' = L33 Z3 + L32 Z2, so the rotations [L33 x] Q =
  // [L33' 0] act on the rows of [Z3; z^T] (z: a row of Z2); the Gram Z^T Z loses the z left.
  auto z = active_lever_solve_.middleRows(base, size);
  Eigen::Matrix<double, 6, 6> gram = active_gram_.middleCols<6>(6 * first);
  for (int c = 0; c < 3; ++c) { // three rank-1 updates of L33
    auto x = sticking_work_.head(k);
    x = l.block(r + 3, r + c, k, 1);
    Vector6 z_row = z.row(r + c).transpose();
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
      const Vector6 zi = (z.row(r + 3 + i).transpose() + sn * z_row) / cs;
      z_row = cs * z_row - sn * zi;
      z.row(r + 3 + i) = zi.transpose();
    }
    gram.noalias() -= z_row * z_row.transpose();
  }
  active_gram_.middleCols<6>(6 * first) = gram;
  for (int row = r; row < size - 3; ++row)
    z.row(row) = z.row(row + 3);
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

bool StickingSolver::append_active_node(const CompliantPatch& patch, const PatchLever& structure,
                                        int node) {
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
  solve_lower_three(l.data(), l.outerStride(), size, b.data(), b.outerStride());
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
  // Z = L^-1 Lambda_A gains the rows d^-1 (Lambda_n - b^T Z_A); Z^T Z gains their Gram.
  auto z = active_lever_solve_.middleRows(base, size + 3);
  Eigen::Matrix<double, 3, 6> z_n = structure.lever.middleRows<3>(3 * node);
  z_n.noalias() -= b.transpose() * z.topRows(size);
  d.triangularView<Eigen::Lower>().solveInPlace(z_n);
  z.bottomRows<3>() = z_n;
  active_gram_.middleCols<6>(6 * first).noalias() += z_n.transpose() * z_n;
  active_order_[first + count] = node;
  active_position_[first + node] = count;
  ++count;
  return true;
}

bool StickingSolver::update_active_factor(const ContactProblem& problem, int j) {
  const CompliantPatch& patch = problem.patches[j];
  const int first = patch.first_contact, n_nodes = patch.n_contacts;
  bool owned = active_version_[j] == problem.patch_levers[j].version && active_first_[j] == first &&
               active_size_[j] == n_nodes;
  for (int k = first; owned && k < first + n_nodes; ++k)
    owned = active_owner_[k] == j;
  if (!owned || active_updates_[j] >= kMaxUpdates) { // start from an empty factor
    active_version_[j] = problem.patch_levers[j].version;
    active_first_[j] = first;
    active_size_[j] = n_nodes;
    active_count_[j] = 0;
    active_updates_[j] = 0;
    active_owner_.segment(first, n_nodes).setConstant(j);
    active_position_.segment(first, n_nodes).setConstant(-1);
    active_gram_.middleCols<6>(6 * first).setZero();
  }
  const bool rebuilding = active_count_[j] == 0;
  for (int i = active_count_[j] - 1; i >= 0; --i) {
    const int node = active_order_[first + i];
    if (!wanted_[first + node]) {
      remove_active_node(first, i);
      active_position_[first + node] = -1;
      --active_count_[j];
      ++active_updates_[j];
    }
  }
  for (int node = 0; node < n_nodes; ++node) {
    if (wanted_[first + node] && active_position_[first + node] < 0) {
      if (!append_active_node(patch, problem.patch_levers[j], node)) {
        active_version_[j] = -1; // not positive definite: start again next time
        return false;
      }
      active_updates_[j] += rebuilding ? 0 : 1;
    }
  }
  return true;
}

void StickingSolver::resize(int max_contacts, int rigid_rank) {
  max_contacts_ = max_contacts;
  rigid_rank_ = rigid_rank;
  const int n3 = 3 * max_contacts;
  sticking_p_.setZero(n3);
  sticking_c_.setZero(n3);
  sticking_full_.setZero(n3);
  sticking_work_.setZero(n3);
  sticking_columns_.setZero(n3, 3);
  active_factor_.setZero(n3, n3);
  active_lever_solve_.setZero(n3, 6);
  active_gram_.setZero(6, 6 * max_contacts);
  active_order_.setConstant(max_contacts, -1);
  active_position_.setConstant(max_contacts, -1);
  active_owner_.setConstant(max_contacts, -1);
  active_version_.setConstant(max_contacts, -1);
  active_first_.setConstant(max_contacts, -1);
  active_size_.setConstant(max_contacts, -1);
  active_count_.setZero(max_contacts);
  active_updates_.setZero(max_contacts);
  wanted_.setZero(max_contacts);
  sliding_.setZero(max_contacts);
  sticking_capacitance_.setZero(rigid_rank, rigid_rank);
  sticking_y_.setZero(rigid_rank);
  sticking_map_.setZero(6, rigid_rank);
  g_sliding_.setZero(rigid_rank);
}

SolverResult StickingSolver::solve(const ContactProblem& problem, const SolverSettings& settings,
                                   Eigen::Ref<Eigen::VectorXd> impulses,
                                   DelassusProducts& products) {
  const int n = problem.n_contacts;
  const int n3 = 3 * n;
  const int m = rigid_rank_;
  SolverResult result;
  if (static_cast<int>(problem.patches.size()) > max_contacts_)
    return result;
  if (problem.patch_levers.size() != problem.patches.size())
    return result;
  int covered = 0;
  for (std::size_t j = 0; j < problem.patches.size(); ++j) {
    const CompliantPatch& patch = problem.patches[j];
    const PatchLever& structure = problem.patch_levers[j];
    if (patch.n_contacts == 0)
      continue;
    if (structure.version <= 0 || !structure.lever_map_valid ||
        structure.lever.rows() != 3 * patch.n_contacts || structure.lever_map.rows() != 6 ||
        structure.lever_map.cols() != m)
      return result;
    covered += patch.n_contacts;
  }
  if (covered != n)
    return result; // a contact without compliance: D singular
  int n_active = 0;
  for (int k = 0; k < n; ++k) { // the warm start's prediction: sticking, sliding or separated
    const double p_n = impulses[3 * k];
    const double t2 =
        impulses[3 * k + 1] * impulses[3 * k + 1] + impulses[3 * k + 2] * impulses[3 * k + 2];
    const double mu = problem.friction[k];
    // Within 1e-9 of the cone (a projected warm start lands there up to round-off): sliding.
    wanted_[k] = p_n > 0.0 && t2 < (1.0 - 1e-9) * mu * mu * p_n * p_n ? 1 : 0;
    sliding_[k] = p_n > 0.0 && !wanted_[k] ? 1 : 0;
    n_active += wanted_[k];
  }
  if (n_active == 0)
    return result;

  // g_S = G^T p_S of the sliding contacts (held at their warm-start impulses).
  auto g_sliding = g_sliding_.head(m);
  g_sliding.setZero();
  for (std::size_t j = 0; j < problem.patches.size(); ++j) {
    const CompliantPatch& patch = problem.patches[j];
    const PatchLever& structure = problem.patch_levers[j];
    Vector6 t = Vector6::Zero();
    bool any = false;
    for (int node = 0; node < patch.n_contacts; ++node) {
      const int k = patch.first_contact + node;
      if (sliding_[k]) {
        add_lever_transposed(structure.lever, node,
                             patch.node_rotation(node).transpose() * impulses.segment<3>(3 * k), t);
        any = true;
      }
    }
    if (any)
      g_sliding.noalias() += structure.lever_map.transpose() * t;
  }

  // x_j = C_j,AA^-1 c'_j,A with c' = c~ + C_AS p~_S + Lambda_A T_j g_S; S and G^T D_A^-1 c'.
  sticking_capacitance_.setIdentity();
  sticking_y_.setZero();
  for (std::size_t j = 0; j < problem.patches.size(); ++j) {
    const CompliantPatch& patch = problem.patches[j];
    const PatchLever& structure = problem.patch_levers[j];
    if (patch.n_contacts == 0)
      continue;
    if (!update_active_factor(problem, static_cast<int>(j))) {
      result.direct_attempt = DirectAttempt::failed;
      return result;
    }
    const int first = patch.first_contact, count = active_count_[j];
    const int size = 3 * patch.n_contacts;
    auto w = products.patch_product.segment(3 * first, size); // C_:S p~_S (patch frame, node order)
    w.setZero();
    for (int node = 0; node < patch.n_contacts; ++node) {
      if (sliding_[first + node]) {
        const Eigen::Vector3d p_patch =
            patch.node_rotation(node).transpose() * impulses.segment<3>(3 * (first + node));
        add_three_columns(patch.compliance_over_dt.col(3 * node).data(),
                          patch.compliance_over_dt.outerStride(), size, p_patch.data(), w.data());
      }
    }
    if (count == 0)
      continue;
    // x = L^-1 c'; Lambda_A^T C_AA^-1 c' = Z^T x.
    auto c = sticking_c_.segment(3 * first, 3 * count);
    auto x = sticking_p_.segment(3 * first, 3 * count);
    const Vector6 u_sliding = structure.lever_map * g_sliding;
    for (int i = 0; i < count; ++i) {
      const int node = active_order_[first + i];
      const int k = first + node;
      Eigen::Vector3d c_k = problem.free_velocity.segment<3>(3 * k);
      c_k[0] += problem.normal_bias[k];
      c.segment<3>(3 * i).noalias() = patch.node_rotation(node).transpose() * c_k;
      x.segment<3>(3 * i) = c.segment<3>(3 * i) + w.segment<3>(3 * node) +
                            lever_times(structure.lever, node, u_sliding);
    }
    solve_lower(&active_factor_(3 * first, 3 * first), active_factor_.outerStride(), 3 * count,
                x.data());
    const Vector6 t = active_lever_solve_.middleRows(3 * first, 3 * count).transpose() * x;
    sticking_y_.noalias() += structure.lever_map.transpose() * t;
    sticking_map_.noalias() = active_gram_.middleCols<6>(6 * first) * structure.lever_map;
    sticking_capacitance_.noalias() += structure.lever_map.transpose() * sticking_map_;
  }
  if (Eigen::internal::llt_inplace<double, Eigen::Lower>::unblocked(sticking_capacitance_) >= 0) {
    result.direct_attempt = DirectAttempt::failed;
    return result;
  }
  auto s = sticking_capacitance_.triangularView<Eigen::Lower>();
  s.solveInPlace(sticking_y_);
  s.transpose().solveInPlace(sticking_y_); // z

  // p~_A, G^T p = G_A^T p_A + g_S; the candidate in contact frames.
  products.rigid.head(m) = g_sliding;
  sticking_full_.head(n3).setZero();
  int n_outside = 0;
  for (int k = 0; k < n; ++k)
    if (sliding_[k])
      sticking_full_.segment<3>(3 * k) = impulses.segment<3>(3 * k);
  for (std::size_t j = 0; j < problem.patches.size(); ++j) {
    const CompliantPatch& patch = problem.patches[j];
    const PatchLever& structure = problem.patch_levers[j];
    const int first = patch.first_contact, count = patch.n_contacts > 0 ? active_count_[j] : 0;
    if (count == 0)
      continue;
    // p~_A = -L^-T (L^-1 c' - Z T z)
    auto x = sticking_p_.segment(3 * first, 3 * count);
    const Vector6 u = structure.lever_map * sticking_y_;
    x.noalias() -= active_lever_solve_.middleRows(3 * first, 3 * count) * u;
    solve_lower_transposed(&active_factor_(3 * first, 3 * first), active_factor_.outerStride(),
                           3 * count, x.data());
    x = -x;
    Vector6 t = Vector6::Zero();
    for (int i = 0; i < count; ++i) {
      const int node = active_order_[first + i];
      add_lever_transposed(structure.lever, node, x.segment<3>(3 * i), t);
      const Eigen::Vector3d p = patch.node_rotation(node) * x.segment<3>(3 * i);
      const double mu = problem.friction[first + node];
      if (!(p[0] >= 0.0) || !(p[1] * p[1] + p[2] * p[2] <= mu * mu * p[0] * p[0]))
        ++n_outside;
      sticking_full_.segment<3>(3 * (first + node)) = p;
    }
    products.rigid.head(m).noalias() += structure.lever_map.transpose() * t;
  }
  if (!sticking_full_.head(n3).allFinite()) {
    result.direct_attempt = DirectAttempt::failed;
    return result;
  }

  // Patch products w = C_j (I (x) R)^T p (patch frame). Rows of A from the sticking
  // equations, C p~ = -(c~ + Lambda T G^T p); the other rows by dot products with their
  // columns (C is symmetric), or all rows by the columns of A and S when those are fewer.
  for (std::size_t j = 0; j < problem.patches.size(); ++j) {
    const CompliantPatch& patch = problem.patches[j];
    const PatchLever& structure = problem.patch_levers[j];
    if (patch.n_contacts == 0)
      continue;
    const int first = patch.first_contact, count = active_count_[j];
    const int size = 3 * patch.n_contacts;
    auto w = products.patch_product.segment(3 * first, size); // holds C_:S p~_S
    auto p_patch = sticking_work_.head(size);                 // p~ in node order
    for (int node = 0; node < patch.n_contacts; ++node)
      p_patch.segment<3>(3 * node).noalias() =
          patch.node_rotation(node).transpose() * sticking_full_.segment<3>(3 * (first + node));
    if (2 * count < patch.n_contacts) { // by the columns of A (w holds those of S)
      for (int i = 0; i < count; ++i) {
        const int node = active_order_[first + i];
        add_three_columns(patch.compliance_over_dt.col(3 * node).data(),
                          patch.compliance_over_dt.outerStride(), size, p_patch.data() + 3 * node,
                          w.data());
      }
    } else {
      if (count > 0) {
        const Vector6 v6 = structure.lever_map * products.rigid.head(m);
        for (int i = 0; i < count; ++i) {
          const int node = active_order_[first + i];
          w.segment<3>(3 * node) =
              -(sticking_c_.segment<3>(3 * (first + i)) + lever_times(structure.lever, node, v6));
        }
      }
      for (int node = 0; node < patch.n_contacts; ++node) {
        if (wanted_[first + node])
          continue;
        for (int c = 0; c < 3; ++c)
          w[3 * node + c] = patch.compliance_over_dt.col(3 * node + c).head(size).dot(p_patch);
      }
    }
  }
  products.velocity.head(n3).noalias() = problem.rigid_factor.topRows(n3) * products.rigid.head(m);
  products.velocity.head(n3) += problem.free_velocity.head(n3);
  products.add_patch_velocities(problem);
  if (n_outside == 0) {
    const double r = products.residual(problem, sticking_full_, products.velocity);
    if (r <= settings.tolerance) {
      impulses.head(n3) = sticking_full_.head(n3);
      result = SolverResult{};
      result.direct = true;
      result.direct_attempt = DirectAttempt::accepted;
      result.iterations = 0;
      result.residual = r;
      result.status = SolverStatus::converged;
      return result;
    }
  }
  // Refused (a sticking contact outside its cone, a held sliding impulse, a separated
  // contact closing): the candidate projected onto the cones is the iterative solver's
  // start, with G^T p and the patch products updated by the projection's change.
  for (int k = 0; k < n && n_outside > 0; ++k) {
    if (!wanted_[k])
      continue;
    const Eigen::Vector3d p = sticking_full_.segment<3>(3 * k);
    const Eigen::Vector3d delta = project_onto_cone(p, problem.friction[k]) - p;
    if (delta.squaredNorm() == 0.0)
      continue;
    sticking_full_.segment<3>(3 * k) += delta;
    add_impulse_change(problem, &problem.patches[products.patch_of[k]], k, delta,
                       products.rigid.data(), products.patch_product.data());
  }
  impulses.head(n3) = sticking_full_.head(n3);
  result.direct_attempt =
      n_outside > 0 ? DirectAttempt::refused_cone : DirectAttempt::refused_residual;
  return result;
}

} // namespace plantar::contact
