// Direct solve on the warm start's active set (part of ContactSolver,
// SolverSettings::sticking_direct).
//
// The warm start predicts, per contact, sticking (p_n > 0, inside the cone by more than a
// relative 1e-9), sliding (p_n > 0 on the cone: S, held at its warm-start impulse) or
// separated (p = 0).
// Sticking contacts then have zero De Saxce velocity: W_AA p_A = -c'_A with
// c' = v_free + b e_n + W_AS p_S. With every contact on a patch whose rigid rows are
// G_j = (I (x) R_j) Lambda_j T_j (CompliantPatch::lever, lever_map) and
// D_A = blockdiag((I (x) R_j) C_j,AA (I (x) R_j)^T), C_j = C/dt^2 in the patch frame,
// Woodbury gives, in patch frames, with H = C_j,AA^-1 and Y = H Lambda_j,A:
//   x_j = H c~'_j,A                                      (one product with H)
//   S z = sum_j T_j^T Y^T c~'_j,A,   S = I_m + sum_j T_j^T (Lambda_A^T Y) T_j
//   p~_j,A = -(x_j - Y T_j z)
// The candidate is kept when every p_A lies in its cone and the natural-map residual of all
// contacts (the separated ones need v_n + b >= 0) meets the tolerance; it is then a solution
// of the contact problem. Otherwise it is projected onto the cones and the iterative solver
// starts from it (with its G^T p and patch products), not from the warm start.
//
// H (symmetric, held in its lower triangle), Y and Lambda_A^T Y are kept between solves and
// updated node by node when A changes: adding a node borders H (a product of H with the
// node's three columns of C and a rank-3 update, O(|A|^2)); removing one swaps it to the end
// and takes the Schur complement (a rank-3 update, O(|A|^2)). H is rebuilt from scratch
// after 60 updates (round-off), or when a 3 x 3 pivot is not positive definite. The product
// with H reads the triangle once, where the two triangular solves with a Cholesky factor it
// replaces are bound by their dependency chains.
#include "coupling/contact/contact_solver.h"

#include "coupling/contact/coulomb_cone.h"
#include "coupling/contact/dense_kernels.h"
#include "coupling/contact/impulse_change.h"

#include <Eigen/Cholesky>
#include <cmath>
#include <utility>

namespace plantar::coupling {

namespace {
using Vector6 = Eigen::Matrix<double, 6, 1>;
constexpr int kMaxUpdates = 60; // factor updates before a rebuild (round-off)
} // namespace

namespace {
// In place: the lower Cholesky factor L of a symmetric 3 x 3 @p s (upper part left); false
// when s is not positive definite.
bool cholesky3(Eigen::Matrix3d& s) {
  for (int j = 0; j < 3; ++j) {
    double djj = s(j, j);
    for (int t = 0; t < j; ++t)
      djj -= s(j, t) * s(j, t);
    if (!(djj > 0.0))
      return false;
    s(j, j) = std::sqrt(djj);
    for (int i = j + 1; i < 3; ++i) {
      double dij = s(i, j);
      for (int t = 0; t < j; ++t)
        dij -= s(i, t) * s(j, t);
      s(i, j) = dij / s(j, j);
    }
  }
  return true;
}

// X <- X L^-T (X: rows x 3, L lower 3 x 3), by columns.
template <typename Block> void solve_right_transposed(const Eigen::Matrix3d& l, Block&& x) {
  x.col(0) /= l(0, 0);
  x.col(1) = (x.col(1) - l(1, 0) * x.col(0)) / l(1, 1);
  x.col(2) = (x.col(2) - l(2, 0) * x.col(0) - l(2, 1) * x.col(1)) / l(2, 2);
}

// G <- L^-1 G (3 x c), L lower 3 x 3.
template <typename Matrix> void solve_lower(const Eigen::Matrix3d& l, Matrix& g) {
  g.row(0) /= l(0, 0);
  g.row(1) = (g.row(1) - l(1, 0) * g.row(0)) / l(1, 1);
  g.row(2) = (g.row(2) - l(2, 0) * g.row(0) - l(2, 1) * g.row(1)) / l(2, 2);
}

// G <- L^-T G (3 x c), L lower 3 x 3.
template <typename Matrix> void solve_upper_transposed(const Eigen::Matrix3d& l, Matrix& g) {
  g.row(2) /= l(2, 2);
  g.row(1) = (g.row(1) - l(2, 1) * g.row(2)) / l(1, 1);
  g.row(0) = (g.row(0) - l(1, 0) * g.row(1) - l(2, 0) * g.row(2)) / l(0, 0);
}

// The lower triangle of H (n x n at @p h) += sign K K^T, K = the first n rows of @p k
// (n x 3), a column at a time (add_three_columns).
template <typename HBlock, typename KBlock>
void add_rank_three(HBlock&& h, const KBlock& k, Eigen::Index n, double sign) {
  for (Eigen::Index i = 0; i < n; ++i) {
    const double d[3] = {sign * k(i, 0), sign * k(i, 1), sign * k(i, 2)};
    add_three_columns(k.data() + i, k.outerStride(), n - i, d, h.data() + i * h.outerStride() + i);
  }
}

// Symmetric permutation of indices a < b of H held in its lower triangle (LAPACK's syswapr).
template <typename HBlock> void swap_symmetric_lower(HBlock&& h, Eigen::Index a, Eigen::Index b) {
  const Eigen::Index n = h.rows();
  std::swap(h(a, a), h(b, b));
  for (Eigen::Index j = 0; j < a; ++j)
    std::swap(h(a, j), h(b, j));
  for (Eigen::Index j = a + 1; j < b; ++j)
    std::swap(h(j, a), h(b, j));
  for (Eigen::Index j = b + 1; j < n; ++j)
    std::swap(h(j, a), h(j, b));
}
} // namespace

bool ContactSolver::remove_active_node(const CompliantPatch& patch, int position) {
  // The node's block is swapped with the last one (H needs no order), then dropped: the
  // inverse without it is the Schur complement H11' = H11 - h Hnn^-1 h^T, h = H(1, n).
  const int first = patch.first_contact;
  const int base = 3 * first;
  const int count = active_count_[active_owner_[first]];
  const int size = 3 * count, last = size - 3, r = 3 * position;
  auto h = active_factor_.block(base, base, size, size);
  auto y = active_lever_solve_.middleRows(base, size);
  if (r != last) {
    for (int c = 0; c < 3; ++c)
      swap_symmetric_lower(h, r + c, last + c);
    y.middleRows<3>(r).swap(y.middleRows<3>(last));
    const int moved = active_order_[first + count - 1];
    active_order_[first + position] = moved;
    active_position_[first + moved] = position;
  }
  Eigen::Matrix3d l = h.block<3, 3>(last, last);
  if (!cholesky3(l)) // H is positive definite; only round-off could break it
    return false;
  auto k = sticking_columns_.topRows(last);
  k = h.block(last, 0, 3, last).transpose();
  // Y = H Lambda_A: Y1' = Y1 - h Hnn^-1 Yn = Y1 - K a with a = L^-1 Yn; Lambda^T Y loses a^T a.
  Eigen::Matrix<double, 3, 6> a = y.middleRows<3>(last);
  solve_lower(l, a);
  solve_right_transposed(l, k);     // K = h L^-T
  add_rank_three(h, k, last, -1.0); // H11 - K K^T
  y.topRows(last).noalias() -= k * a;
  Eigen::Matrix<double, 6, 6> gram = active_gram_.middleCols<6>(6 * first);
  gram.noalias() -= a.transpose() * a;
  active_gram_.middleCols<6>(6 * first) = 0.5 * (gram + gram.transpose());
  return true;
}

bool ContactSolver::append_active_node(const CompliantPatch& patch, int node) {
  // Bordering: with B = C_A,n, U = H B and S = C_nn - B^T U = L L^T (3 x 3),
  //   H' = [H + U S^-1 U^T, -U S^-1; -S^-1 U^T, S^-1];  with K = U L^-T, U S^-1 = K L^-1.
  const int first = patch.first_contact;
  const int base = 3 * first;
  int& count = active_count_[active_owner_[first]];
  const int size = 3 * count;
  auto h = active_factor_.block(base, base, size + 3, size + 3);
  auto b = sticking_columns_.topRows(size);
  for (int i = 0; i < count; ++i)
    b.middleRows<3>(3 * i) =
        patch.compliance_over_dt.block<3, 3>(3 * active_order_[first + i], 3 * node);
  auto u = sticking_product_.topRows(size);
  if (size > 0)
    symmetric_lower_times_three(h.data(), h.outerStride(), size, b.data(), b.outerStride(),
                                u.data(), u.outerStride());
  Eigen::Matrix3d l = patch.compliance_over_dt.block<3, 3>(3 * node, 3 * node);
  l.noalias() -= b.transpose() * u;
  l = (0.5 * (l + l.transpose())).eval();
  if (!cholesky3(l))
    return false;
  // Y = H Lambda_A: with r = Lambda_n - B^T Y and g = L^-1 r, Y_A' = Y_A - K g, Y_n = L^-T g;
  // Z^T Z = Lambda_A^T Y gains g^T g.
  auto y = active_lever_solve_.middleRows(base, size + 3);
  Eigen::Matrix<double, 3, 6> g = patch.lever.middleRows<3>(3 * node);
  g.noalias() -= b.transpose() * y.topRows(size);
  solve_lower(l, g);
  solve_right_transposed(l, u); // K
  add_rank_three(h, u, size, 1.0);
  y.topRows(size).noalias() -= u * g;
  y.bottomRows<3>() = g;
  Eigen::Matrix<double, 6, 6> gram = active_gram_.middleCols<6>(6 * first);
  gram.noalias() += g.transpose() * g;
  active_gram_.middleCols<6>(6 * first) = 0.5 * (gram + gram.transpose());
  auto y_n = y.bottomRows<3>();
  solve_upper_transposed(l, y_n);
  // -K L^-1 (by columns, last first) and S^-1 = L^-T L^-1.
  u.col(2) /= l(2, 2);
  u.col(1) = (u.col(1) - l(2, 1) * u.col(2)) / l(1, 1);
  u.col(0) = (u.col(0) - l(1, 0) * u.col(1) - l(2, 0) * u.col(2)) / l(0, 0);
  h.block(size, 0, 3, size) = -u.transpose();
  Eigen::Matrix3d l_inverse = Eigen::Matrix3d::Identity();
  solve_lower(l, l_inverse);
  h.block<3, 3>(size, size).noalias() = l_inverse.transpose() * l_inverse;
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
  if (!owned || active_updates_[j] >= kMaxUpdates) { // start from an empty factor
    active_version_[j] = patch.sticking_version;
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
      if (!remove_active_node(patch, i)) {
        active_version_[j] = -1; // not positive definite: start again next time
        return false;
      }
      active_position_[first + node] = -1;
      --active_count_[j];
      ++active_updates_[j];
    }
  }
  for (int node = 0; node < n_nodes; ++node) {
    if (wanted_[first + node] && active_position_[first + node] < 0) {
      if (!append_active_node(patch, node)) {
        active_version_[j] = -1; // not positive definite: start again next time
        return false;
      }
      active_updates_[j] += rebuilding ? 0 : 1;
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
    return false;

  start_ready_ = false; // rigid_work_ and patch_velocity_ are taken from here on
  // g_S = G^T p_S of the sliding contacts (held at their warm-start impulses).
  auto g_sliding = rigid_work2_.head(m);
  g_sliding.setZero();
  for (const CompliantPatch& patch : problem.patches) {
    Vector6 t = Vector6::Zero();
    bool any = false;
    for (int node = 0; node < patch.n_contacts; ++node) {
      const int k = patch.first_contact + node;
      if (sliding_[k]) {
        t.noalias() += patch.lever.middleRows<3>(3 * node).transpose() *
                       (patch.rotation.transpose() * impulses.segment<3>(3 * k));
        any = true;
      }
    }
    if (any)
      g_sliding.noalias() += patch.lever_map.transpose() * t;
  }

  // x_j = C_j,AA^-1 c'_j,A with c' = c~ + C_AS p~_S + Lambda_A T_j g_S; S and G^T D_A^-1 c'.
  sticking_capacitance_.setIdentity();
  sticking_y_.setZero();
  for (std::size_t j = 0; j < problem.patches.size(); ++j) {
    const CompliantPatch& patch = problem.patches[j];
    if (patch.n_contacts == 0)
      continue;
    if (!update_active_factor(problem, static_cast<int>(j)))
      return false;
    const int first = patch.first_contact, count = active_count_[j];
    const int size = 3 * patch.n_contacts;
    auto w = patch_velocity_.segment(3 * first, size); // C_:S p~_S (patch frame, node order)
    w.setZero();
    for (int node = 0; node < patch.n_contacts; ++node) {
      if (sliding_[first + node]) {
        const Eigen::Vector3d p_patch =
            patch.rotation.transpose() * impulses.segment<3>(3 * (first + node));
        add_three_columns(patch.compliance_over_dt.col(3 * node).data(),
                          patch.compliance_over_dt.outerStride(), size, p_patch.data(), w.data());
      }
    }
    if (count == 0)
      continue;
    // x = H c'; Lambda_A^T C_AA^-1 c' = Y^T c'.
    auto c = sticking_c_.segment(3 * first, 3 * count);
    auto c_prime = sticking_work_.head(3 * count);
    auto x = sticking_p_.segment(3 * first, 3 * count);
    const Vector6 u_sliding = patch.lever_map * g_sliding;
    for (int i = 0; i < count; ++i) {
      const int node = active_order_[first + i];
      const int k = first + node;
      Eigen::Vector3d c_k = problem.free_velocity.segment<3>(3 * k);
      c_k[0] += problem.normal_bias[k];
      c.segment<3>(3 * i).noalias() = patch.rotation.transpose() * c_k;
      c_prime.segment<3>(3 * i) = c.segment<3>(3 * i) + w.segment<3>(3 * node) +
                                  patch.lever.middleRows<3>(3 * node) * u_sliding;
    }
    x.noalias() = active_factor_.block(3 * first, 3 * first, 3 * count, 3 * count)
                      .selfadjointView<Eigen::Lower>() *
                  c_prime;
    const Vector6 t = active_lever_solve_.middleRows(3 * first, 3 * count).transpose() * c_prime;
    sticking_y_.noalias() += patch.lever_map.transpose() * t;
    sticking_map_.noalias() = active_gram_.middleCols<6>(6 * first) * patch.lever_map;
    sticking_capacitance_.noalias() += patch.lever_map.transpose() * sticking_map_;
  }
  if (Eigen::internal::llt_inplace<double, Eigen::Lower>::unblocked(sticking_capacitance_) >= 0)
    return false;
  auto s = sticking_capacitance_.triangularView<Eigen::Lower>();
  s.solveInPlace(sticking_y_);
  s.transpose().solveInPlace(sticking_y_); // z

  // p~_A, G^T p = G_A^T p_A + g_S; the candidate in contact frames.
  rigid_work_.head(m) = g_sliding;
  sticking_full_.head(n3).setZero();
  int n_outside = 0;
  for (int k = 0; k < n; ++k)
    if (sliding_[k])
      sticking_full_.segment<3>(3 * k) = impulses.segment<3>(3 * k);
  for (std::size_t j = 0; j < problem.patches.size(); ++j) {
    const CompliantPatch& patch = problem.patches[j];
    const int first = patch.first_contact, count = patch.n_contacts > 0 ? active_count_[j] : 0;
    if (count == 0)
      continue;
    // p~_A = -(H c' - Y T z)
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
        ++n_outside;
      sticking_full_.segment<3>(3 * (first + node)) = p;
    }
    rigid_work_.head(m).noalias() += patch.lever_map.transpose() * t;
  }
  if (!sticking_full_.head(n3).allFinite())
    return false;

  // Patch products w = C_j (I (x) R)^T p (patch frame). Rows of A from the sticking
  // equations, C p~ = -(c~ + Lambda T G^T p); the other rows by dot products with their
  // columns (C is symmetric), or all rows by the columns of A and S when those are fewer.
  for (std::size_t j = 0; j < problem.patches.size(); ++j) {
    const CompliantPatch& patch = problem.patches[j];
    if (patch.n_contacts == 0)
      continue;
    const int first = patch.first_contact, count = active_count_[j];
    const int size = 3 * patch.n_contacts;
    auto w = patch_velocity_.segment(3 * first, size); // holds C_:S p~_S
    auto p_patch = sticking_work_.head(size);          // p~ in node order
    for (int node = 0; node < patch.n_contacts; ++node)
      p_patch.segment<3>(3 * node).noalias() =
          patch.rotation.transpose() * sticking_full_.segment<3>(3 * (first + node));
    if (2 * count < patch.n_contacts) { // by the columns of A (w holds those of S)
      for (int i = 0; i < count; ++i) {
        const int node = active_order_[first + i];
        add_three_columns(patch.compliance_over_dt.col(3 * node).data(),
                          patch.compliance_over_dt.outerStride(), size, p_patch.data() + 3 * node,
                          w.data());
      }
    } else {
      if (count > 0) {
        const Vector6 v6 = patch.lever_map * rigid_work_.head(m);
        for (int i = 0; i < count; ++i) {
          const int node = active_order_[first + i];
          w.segment<3>(3 * node).noalias() =
              -(sticking_c_.segment<3>(3 * (first + i)) + patch.lever.middleRows<3>(3 * node) * v6);
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
  velocity_.head(n3).noalias() = problem.rigid_factor.topRows(n3) * rigid_work_.head(m);
  velocity_.head(n3) += problem.free_velocity.head(n3);
  add_patch_velocities(problem);
  if (n_outside == 0) {
    const double r = residual(problem, sticking_full_, velocity_);
    if (r <= settings.tolerance) {
      impulses.head(n3) = sticking_full_.head(n3);
      result = SolverResult{};
      result.direct = true;
      result.iterations = 0;
      result.residual = r;
      result.status = SolverStatus::converged;
      return true;
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
    add_impulse_change(problem, &problem.patches[patch_of_[k]], k, delta, rigid_work_.data(),
                       patch_velocity_.data());
  }
  impulses.head(n3) = sticking_full_.head(n3);
  start_ready_ = true;
  return false;
}

} // namespace plantar::coupling
