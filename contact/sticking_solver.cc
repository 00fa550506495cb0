// Direct solve on the warm start's active set (StickingSolver, sticking_solver.h).
//
// The warm start predicts, per contact, sticking (p_n > 0, inside the cone by more than a
// relative 1e-9: the set A), sliding (p_n > 0 on the cone: the set S, with the direction d of
// its tangential impulse) or separated (p = 0). Loaded contacts (A and S) have zero normal
// velocity; sticking ones zero tangential velocity; a sliding one's impulse is p = p_n (1, mu d)
// and its tangential velocity sigma is free:
//   W_LL p_L + c'_L = E sigma,   H^T p_L = 0,   c' = v_free + b e_n,   L = A u S,
// with E the tangential directions of the S rows and H_s = E_s - mu_s n_s d_s^T (H^T p = p_t -
// mu p_n d). With every contact on a patch whose rigid rows are G_j = (I (x) R_j) Lambda_j T_j
// (ContactProblem::patch_levers: lever, lever_map) and D = blockdiag((I (x) R_j) C_j,LL (I (x)
// R_j)^T), C_j = C/dt^2 in the patch frame, Woodbury gives, in patch frames, with
// L L^T = C_j,LL and Z = L^-1 Lambda_j,L:
//   x_j = L^-1 c~'_j                                     (one triangular solve)
//   S z0 = sum_j T_j^T Z^T x_j,   S = I_m + sum_j T_j^T (Z^T Z) T_j,   y0_j = x_j - Z T_j z0
// (p0 = -L^-T y0 is the all-sticking solution). With E~ = L^-1 E, H~ = L^-1 H (nonzero only
// in the factor's last rows, the tail, where S sits) and B_E = sum_j T_j^T Z^T E~_j, B_H
// likewise, the slip solves the small system
//   (H~^T E~ - B_H^T S^-1 B_E) sigma = H~^T y0,
// d is replaced by -sigma/|sigma| until it stops changing, and
//   p~_L = -L^-T (y0 - E~ sigma + Z T_j S^-1 B_E sigma)  (one triangular solve).
// The candidate is kept when every sticking p lies in its cone, every sliding p_n >= 0 and the
// natural-map residual of all contacts (the separated ones need v_n + b >= 0) meets the
// tolerance; it is then a solution of the contact problem. Otherwise the active set changes
// (a sticking contact outside its cone slides, one with p_n < 0 separates, a sliding one whose
// slip runs along its friction sticks, a separated one closing sticks) and the solve repeats,
// up to SolverSettings::sticking_rounds sets; the last candidate, projected onto the cones, is
// the iterative solver's start (with its G^T p and patch products), not the warm start.
//
// L, Z and Z^T Z are kept between solves and updated node by node when L changes: adding a
// node is a triangular solve for its rows of L and Z (O(|L|^2)); removing one is a rank-3
// update of the trailing factor whose rotations also update Z and Z^T Z (O(|L|^2)); the
// factor is rebuilt from scratch after max(60, |L|/2) updates. A node that starts sliding
// moves to the tail (removed, appended); E~ and H~ cost O(|tail|^2) per column.
#include "contact/sticking_solver.h"

#include "contact/coulomb_cone.h"
#include "contact/dense_kernels.h"
#include "contact/dense_lu.h"
#include "contact/impulse_change.h"

#include <Eigen/Cholesky>
#include <algorithm>
#include <cmath>

namespace plantar::contact {
namespace {
using Vector6 = Eigen::Matrix<double, 6, 1>;
constexpr int kMaxUpdates = 60; // factor updates before a rebuild (round-off), at least

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
  // A rebuild costs O(|L|^3), an update O(|L|^2): at least |L|/2 updates between rebuilds.
  if (!owned || active_updates_[j] >= std::max(kMaxUpdates, active_count_[j] / 2)) {
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
  for (int pass = 0; pass < 2; ++pass) { // sticking nodes first, sliding ones last
    for (int node = 0; node < n_nodes; ++node) {
      const int k = first + node;
      if (wanted_[k] && sliding_[k] == pass && active_position_[k] < 0) {
        if (!append_active_node(patch, problem.patch_levers[j], node)) {
          active_version_[j] = -1; // not positive definite: start again next time
          return false;
        }
        active_updates_[j] += rebuilding ? 0 : 1;
      }
    }
  }
  // The sliding nodes in the tail: when it holds more than 2 |S_j| + 8 nodes, those before the
  // last |S_j| positions move to the end (then the tail holds at most 2 |S_j|).
  int n_slide = 0, tail = active_count_[j];
  for (int i = 0; i < active_count_[j]; ++i)
    if (sliding_[first + active_order_[first + i]]) {
      ++n_slide;
      tail = std::min(tail, i);
    }
  if (active_count_[j] - tail > 2 * n_slide + 8) {
    const int keep = active_count_[j] - n_slide;
    int moved = 0;
    for (int i = tail; i < keep - moved;) {
      const int node = active_order_[first + i];
      if (!sliding_[first + node]) {
        ++i;
        continue;
      }
      remove_active_node(first, i);
      active_position_[first + node] = -1;
      --active_count_[j];
      if (!append_active_node(patch, problem.patch_levers[j], node)) {
        active_version_[j] = -1;
        return false;
      }
      active_updates_[j] += 2;
      ++moved;
    }
  }
  return true;
}

void StickingSolver::resize(int max_contacts, int rigid_rank) {
  max_contacts_ = max_contacts;
  rigid_rank_ = rigid_rank;
  max_sliding_ = std::min(max_contacts, 256);
  const int n3 = 3 * max_contacts, s = max_sliding_, m = rigid_rank;
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
  direction_.setZero(2, max_contacts);
  sticking_capacitance_.setZero(m, m);
  sticking_y_.setZero(m);
  sticking_map_.setZero(6, m);
  slide_contact_.setZero(s);
  slide_flip_.setZero(s);
  slide_e_.setZero(n3, 2 * s);
  slide_n_.setZero(n3, s);
  slide_be_.setZero(m, 2 * s);
  slide_bn_.setZero(m, s);
  slide_x_.setZero(m, 2 * s);
  slide_gee_.setZero(2 * s, 2 * s);
  slide_gne_.setZero(s, 2 * s);
  slide_matrix_.setZero(2 * s, 2 * s);
  slide_pivots_.setZero(3 * s);
  slide_jacobian_.setZero(s, s);
  slide_columns_.setZero(2 * s, s);
  slide_f_.setZero(s);
  slide_re_.setZero(4 * s); // E~^T y0, then scratch
  slide_rn_.setZero(s);
  slide_sigma_.setZero(2 * s);
  slide_m_.setZero(m);
}

int StickingSolver::solve_active_set(const ContactProblem& problem, DelassusProducts& products) {
  const int n3 = 3 * problem.n_contacts;
  const int m = rigid_rank_;
  const auto patch_count = static_cast<int>(problem.patches.size());
  // 1. x_j = L^-1 c~_j; S and sum_j T_j^T Z^T x_j.
  sticking_capacitance_.setIdentity();
  sticking_y_.setZero();
  for (int j = 0; j < patch_count; ++j) {
    const CompliantPatch& patch = problem.patches[j];
    const PatchLever& structure = problem.patch_levers[j];
    const int first = patch.first_contact, count = patch.n_contacts > 0 ? active_count_[j] : 0;
    if (count == 0)
      continue;
    auto c = sticking_c_.segment(3 * first, 3 * count);
    auto x = sticking_p_.segment(3 * first, 3 * count);
    for (int i = 0; i < count; ++i) {
      const int node = active_order_[first + i];
      const int k = first + node;
      Eigen::Vector3d c_k = problem.free_velocity.segment<3>(3 * k);
      c_k[0] += problem.normal_bias[k];
      c.segment<3>(3 * i).noalias() = patch.node_rotation(node).transpose() * c_k;
    }
    x = c;
    solve_lower(&active_factor_(3 * first, 3 * first), active_factor_.outerStride(), 3 * count,
                x.data());
    const Vector6 t = active_lever_solve_.middleRows(3 * first, 3 * count).transpose() * x;
    sticking_y_.noalias() += structure.lever_map.transpose() * t;
    sticking_map_.noalias() = active_gram_.middleCols<6>(6 * first) * structure.lever_map;
    sticking_capacitance_.noalias() += structure.lever_map.transpose() * sticking_map_;
  }
  if (Eigen::internal::llt_inplace<double, Eigen::Lower>::unblocked(sticking_capacitance_) >= 0)
    return -1;
  auto cap = sticking_capacitance_.triangularView<Eigen::Lower>();
  cap.solveInPlace(sticking_y_);
  cap.transpose().solveInPlace(sticking_y_); // z0
  // y_j += sign Z T_j w (w: m) on every patch's factor rows.
  const auto add_lever_solve = [&](const Eigen::VectorXd& w, double sign) {
    for (int j = 0; j < patch_count; ++j) {
      const int first = problem.patches[j].first_contact;
      const int count = problem.patches[j].n_contacts > 0 ? active_count_[j] : 0;
      if (count == 0)
        continue;
      const Vector6 u = sign * (problem.patch_levers[j].lever_map * w);
      sticking_p_.segment(3 * first, 3 * count).noalias() +=
          active_lever_solve_.middleRows(3 * first, 3 * count) * u;
    }
  };
  // 2. y0_j = x_j - Z T_j z0.
  add_lever_solve(sticking_y_, -1.0);
  // 3. The slip sigma of the sliding contacts (tangential velocities, contact frames).
  const int s = n_sliding_;
  slide_stick_ = false;
  if (s > 0) {
    int g = 0;
    for (int j = 0; j < patch_count; ++j) {
      const CompliantPatch& patch = problem.patches[j];
      const PatchLever& structure = problem.patch_levers[j];
      const int first = patch.first_contact, count = patch.n_contacts > 0 ? active_count_[j] : 0;
      int tail = count;
      for (int i = 0; i < count; ++i)
        if (sliding_[first + active_order_[first + i]]) {
          tail = i;
          break;
        }
      if (tail == count)
        continue;
      const int base = 3 * (first + tail), rows = 3 * (count - tail), g0 = g;
      const auto z = active_lever_solve_.middleRows(base, rows);
      for (int i = tail; i < count; ++i) {
        const int node = active_order_[first + i];
        if (!sliding_[first + node])
          continue;
        slide_contact_[g] = first + node;
        const Eigen::Matrix3d a = patch.node_rotation(node); // contact = a patch
        const int r = 3 * (first + i);
        for (int col = 0; col < 3; ++col) { // n, t1, t2 in the patch frame, through L^-1
          double* v = col == 0 ? &slide_n_(0, g) : &slide_e_(0, 2 * g + col - 1);
          std::fill(v + base, v + base + rows, 0.0);
          v[r] = a(col, 0);
          v[r + 1] = a(col, 1);
          v[r + 2] = a(col, 2);
          solve_lower(&active_factor_(r, r), active_factor_.outerStride(), base + rows - r, v + r);
        }
        ++g;
      }
      // B_E, B_N and the Grams on this patch's tail rows; E~^T y0, N~^T y0.
      const auto e = slide_e_.block(base, 2 * g0, rows, 2 * (g - g0));
      const auto nn = slide_n_.block(base, g0, rows, g - g0);
      const auto y0 = sticking_p_.segment(base, rows);
      // (column by column: no Eigen product here needs scratch memory)
      for (int c = 0; c < 2 * (g - g0); ++c) {
        const Vector6 ze = z.transpose() * e.col(c);
        slide_be_.col(2 * g0 + c).noalias() = structure.lever_map.transpose() * ze;
        slide_re_[2 * g0 + c] = e.col(c).dot(y0);
        for (int c2 = 0; c2 < 2 * (g - g0); ++c2)
          slide_gee_(2 * g0 + c2, 2 * g0 + c) = e.col(c2).dot(e.col(c));
        for (int c2 = 0; c2 < g - g0; ++c2)
          slide_gne_(g0 + c2, 2 * g0 + c) = nn.col(c2).dot(e.col(c));
      }
      for (int c = 0; c < g - g0; ++c) {
        const Vector6 zn = z.transpose() * nn.col(c);
        slide_bn_.col(g0 + c).noalias() = structure.lever_map.transpose() * zn;
        slide_rn_[g0 + c] = nn.col(c).dot(y0);
      }
    }
    // X = S^-1 B_E.
    auto x = slide_x_.leftCols(2 * s);
    x = slide_be_.leftCols(2 * s);
    for (int c = 0; c < 2 * s; ++c) {
      cap.solveInPlace(x.col(c));
      cap.transpose().solveInPlace(x.col(c));
    }
    // M sigma = H~^T y0 with M = H~^T E~ - B_H^T X, H~ = E~ - N~ Dm, Dm(g, 2g..2g+1) = mu d^T.
    // The directions solve F_g = d_g^perp . sigma_g(d) = 0 (the slip along -d_g) by Newton on
    // their angles: d sigma / d d_g[a] = -mu_g q_g M^-1 e_2g+a, the rows of dM and dr, with
    // q_g = N~_g^T y0 - (N~_g^T E~ - B_N(:, g)^T X) sigma.
    auto matrix = slide_matrix_.topLeftCorner(2 * s, 2 * s);
    auto sigma = slide_sigma_.head(2 * s);
    auto pivots = slide_pivots_.head(2 * s);
    auto jacobian = slide_jacobian_.topLeftCorner(s, s);
    auto f = slide_f_.head(s);
    constexpr int kNewtonIterations = 30;
    for (int iteration = 0;; ++iteration) {
      matrix.setZero();
      // The diagonal blocks (per patch): E~^T E~ - Dm^T N~^T E~; the right-hand side.
      for (int g1 = 0; g1 < s; ++g1) {
        const int k1 = slide_contact_[g1];
        const Eigen::Vector2d dm = problem.friction[k1] * direction_.col(k1);
        for (int g2 = 0; g2 < s; ++g2) {
          if (products.patch_of[slide_contact_[g2]] != products.patch_of[k1])
            continue;
          matrix.block<2, 2>(2 * g1, 2 * g2) =
              slide_gee_.block<2, 2>(2 * g1, 2 * g2) - dm * slide_gne_.block<1, 2>(g1, 2 * g2);
        }
        sigma.segment<2>(2 * g1) = slide_re_.segment<2>(2 * g1) - dm * slide_rn_[g1];
      }
      // - B_H^T X, B_H = B_E - B_N Dm.
      auto row = slide_re_.segment(2 * s, 2 * s); // scratch: B_H(:, r)^T X
      for (int g1 = 0; g1 < s; ++g1) {
        const int k1 = slide_contact_[g1];
        const Eigen::Vector2d dm = problem.friction[k1] * direction_.col(k1);
        for (int a = 0; a < 2; ++a) {
          slide_m_ = slide_be_.col(2 * g1 + a) - dm[a] * slide_bn_.col(g1);
          row.noalias() = x.transpose() * slide_m_;
          matrix.row(2 * g1 + a) -= row.transpose();
        }
      }
      if (!lu_in_place(matrix, pivots))
        return -1;
      lu_solve_in_place(matrix, pivots, sigma);
      bool converged = true;
      for (int g1 = 0; g1 < s; ++g1) {
        const Eigen::Vector2d d = direction_.col(slide_contact_[g1]);
        const Eigen::Vector2d slip = sigma.segment<2>(2 * g1);
        f[g1] = d[0] * slip[1] - d[1] * slip[0];
        converged = converged && std::abs(f[g1]) <= 1e-12 * slip.norm() + 1e-300;
      }
      if (converged || iteration + 1 == kNewtonIterations)
        break;
      // The Jacobian of F in the angles, J Delta = -F.
      slide_m_.noalias() = x * sigma;
      for (int h = 0; h < s; ++h) {
        const int kh = slide_contact_[h];
        double q = slide_rn_[h] + slide_bn_.col(h).dot(slide_m_);
        for (int c = 0; c < s; ++c)
          if (products.patch_of[slide_contact_[c]] == products.patch_of[kh])
            q -= slide_gne_.block<1, 2>(h, 2 * c).dot(sigma.segment<2>(2 * c));
        auto column = slide_columns_.col(h).head(2 * s);
        column.setZero();
        column[2 * h] = -direction_(1, kh); // d_h^perp
        column[2 * h + 1] = direction_(0, kh);
        lu_solve_in_place(matrix, pivots, column);
        column *= -problem.friction[kh] * q;
      }
      for (int g1 = 0; g1 < s; ++g1) {
        const Eigen::Vector2d d = direction_.col(slide_contact_[g1]);
        const Eigen::Vector2d perp(-d[1], d[0]);
        for (int h = 0; h < s; ++h)
          jacobian(g1, h) = perp.dot(slide_columns_.block<2, 1>(2 * g1, h));
        jacobian(g1, g1) -= d.dot(sigma.segment<2>(2 * g1));
      }
      if (!lu_in_place(jacobian, slide_pivots_.segment(2 * s, s)))
        break;
      f = -f;
      lu_solve_in_place(jacobian, slide_pivots_.segment(2 * s, s), f);
      for (int g1 = 0; g1 < s; ++g1) {
        const int k1 = slide_contact_[g1];
        const double step = std::clamp(f[g1], -0.5, 0.5);
        const Eigen::Vector2d d = direction_.col(k1);
        direction_.col(k1) = std::cos(step) * d + std::sin(step) * Eigen::Vector2d(-d[1], d[0]);
      }
    }
    slide_flip_.head(s).setZero();
    for (int g1 = 0; g1 < s; ++g1) {
      if (direction_.col(slide_contact_[g1]).dot(sigma.segment<2>(2 * g1)) > 0.0) {
        slide_flip_[g1] = 1; // slips along its friction: it should stick
        slide_stick_ = true;
      }
    }
    // y = y0 - E~ sigma + Z T_j X sigma.
    slide_m_.noalias() = x * sigma;
    add_lever_solve(slide_m_, 1.0);
    for (g = 0; g < s; ++g) { // E~ sigma, on the rows from the node's position down
      const int j = products.patch_of[slide_contact_[g]];
      const int base = 3 * problem.patches[j].first_contact, rows = 3 * active_count_[j];
      for (int row = 3 * active_position_[slide_contact_[g]]; row < rows; ++row)
        sticking_p_[base + row] -= slide_e_(base + row, 2 * g) * sigma[2 * g] +
                                   slide_e_(base + row, 2 * g + 1) * sigma[2 * g + 1];
    }
  }
  // 4. p~_L = -L^-T y; G^T p; the candidate in contact frames.
  products.rigid.head(m).setZero();
  sticking_full_.head(n3).setZero();
  int n_outside = 0;
  for (int j = 0; j < patch_count; ++j) {
    const CompliantPatch& patch = problem.patches[j];
    const PatchLever& structure = problem.patch_levers[j];
    const int first = patch.first_contact, count = patch.n_contacts > 0 ? active_count_[j] : 0;
    if (count == 0)
      continue;
    auto x = sticking_p_.segment(3 * first, 3 * count);
    solve_lower_transposed(&active_factor_(3 * first, 3 * first), active_factor_.outerStride(),
                           3 * count, x.data());
    x = -x;
    Vector6 t = Vector6::Zero();
    for (int i = 0; i < count; ++i) {
      const int node = active_order_[first + i];
      const int k = first + node;
      add_lever_transposed(structure.lever, node, x.segment<3>(3 * i), t);
      const Eigen::Vector3d p = patch.node_rotation(node) * x.segment<3>(3 * i);
      const double mu = problem.friction[k];
      if (sliding_[k] ? !(p[0] >= 0.0)
                      : !(p[0] >= 0.0) || !(p[1] * p[1] + p[2] * p[2] <= mu * mu * p[0] * p[0]))
        ++n_outside;
      sticking_full_.segment<3>(3 * k) = p;
    }
    products.rigid.head(m).noalias() += structure.lever_map.transpose() * t;
  }
  if (!sticking_full_.head(n3).allFinite())
    return -1;

  // 5. Patch products w = C_j (I (x) R)^T p (patch frame). Rows of L from their equations,
  // C p~ = -(c~ + Lambda T G^T p) (+ the slip E sigma on S rows); the other rows by dot
  // products with their columns (C is symmetric), or all rows by the columns of L when
  // those are fewer.
  for (int j = 0; j < patch_count; ++j) {
    const CompliantPatch& patch = problem.patches[j];
    const PatchLever& structure = problem.patch_levers[j];
    if (patch.n_contacts == 0)
      continue;
    const int first = patch.first_contact, count = active_count_[j];
    const int size = 3 * patch.n_contacts;
    auto w = products.patch_product.segment(3 * first, size);
    auto p_patch = sticking_work_.head(size); // p~ in node order
    for (int node = 0; node < patch.n_contacts; ++node)
      p_patch.segment<3>(3 * node).noalias() =
          patch.node_rotation(node).transpose() * sticking_full_.segment<3>(3 * (first + node));
    if (2 * count < patch.n_contacts) { // by the columns of L
      w.setZero();
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
        for (int g = 0; g < s; ++g) {
          const int k = slide_contact_[g];
          if (products.patch_of[k] != j)
            continue;
          const Eigen::Matrix3d a = patch.node_rotation(k - first);
          w.segment<3>(3 * (k - first)).noalias() += a.row(1).transpose() * slide_sigma_[2 * g] +
                                                     a.row(2).transpose() * slide_sigma_[2 * g + 1];
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
  return n_outside;
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
  int n_sticking = 0;
  n_sliding_ = 0;
  for (int k = 0; k < n; ++k) { // the warm start's prediction: sticking, sliding or separated
    const double p_n = impulses[3 * k];
    const Eigen::Vector2d p_t = impulses.segment<2>(3 * k + 1);
    const double mu = problem.friction[k];
    // Within 1e-9 of the cone (a projected warm start lands there up to round-off): sliding.
    const bool inside = p_n > 0.0 && p_t.squaredNorm() < (1.0 - 1e-9) * mu * mu * p_n * p_n;
    wanted_[k] = p_n > 0.0 ? 1 : 0;
    sliding_[k] = p_n > 0.0 && !inside ? 1 : 0;
    if (sliding_[k])
      direction_.col(k) =
          p_t.norm() > 0.0 ? Eigen::Vector2d(p_t.normalized()) : Eigen::Vector2d(1.0, 0.0);
    n_sticking += inside ? 1 : 0;
    n_sliding_ += sliding_[k];
  }
  if (n_sticking == 0)
    return result;

  // The slip's solve costs O(s^3) (tail solves, Grams, Newton) against O(|L|^2) for the rest:
  // beyond s = |L|^(2/3) sliding contacts the iteration is cheaper (measured on the walks'
  // reduced soles, docs/performance.md).
  int n_loaded = 0;
  for (int k = 0; k < n; ++k)
    n_loaded += wanted_[k];
  const int sliding_cap =
      std::min(max_sliding_, std::max(8, static_cast<int>(std::cbrt(double(n_loaded) * n_loaded))));
  const int rounds = std::max(1, settings.sticking_rounds);
  int n_outside = 0;
  bool solved = false;
  for (int round = 0; round < rounds; ++round) {
    if (n_sliding_ > sliding_cap) // too many to solve for their slip: iterate
      break;
    for (std::size_t j = 0; j < problem.patches.size(); ++j) {
      if (problem.patches[j].n_contacts > 0 &&
          !update_active_factor(problem, static_cast<int>(j))) {
        result.direct_attempt = DirectAttempt::failed;
        return result;
      }
    }
    n_outside = solve_active_set(problem, products);
    solved = true;
    if (n_outside < 0) {
      result.direct_attempt = DirectAttempt::failed;
      return result;
    }
    if (n_outside == 0 && !slide_stick_) {
      const double residual = products.residual(problem, sticking_full_, products.velocity);
      if (residual <= settings.tolerance) {
        impulses.head(n3) = sticking_full_.head(n3);
        result = SolverResult{};
        result.direct = true;
        result.direct_attempt = DirectAttempt::accepted;
        result.iterations = 0;
        result.residual = residual;
        result.status = SolverStatus::converged;
        return result;
      }
    }
    if (round + 1 == rounds)
      break;
    // The next active set.
    bool changed = false;
    for (int k = 0; k < n; ++k) {
      const Eigen::Vector3d p = sticking_full_.segment<3>(3 * k);
      const double mu = problem.friction[k];
      if (wanted_[k] && !(p[0] > 0.0)) { // pulled: separates
        wanted_[k] = sliding_[k] = 0;
        changed = true;
      } else if (wanted_[k] && !sliding_[k] &&
                 !(p[1] * p[1] + p[2] * p[2] <= mu * mu * p[0] * p[0])) { // slides
        sliding_[k] = 1;
        direction_.col(k) = p.tail<2>().normalized();
        changed = true;
      } else if (!wanted_[k] &&
                 products.velocity[3 * k] + problem.normal_bias[k] < -settings.tolerance) {
        wanted_[k] = 1; // closing: sticks
        changed = true;
      }
    }
    for (int g = 0; g < n_sliding_ && slide_stick_; ++g) {
      if (slide_flip_[g]) { // slips along its friction: sticks
        sliding_[slide_contact_[g]] = 0;
        changed = true;
      }
    }
    if (!changed)
      break;
    n_sliding_ = 0;
    for (int k = 0; k < n; ++k)
      n_sliding_ += sliding_[k];
  }
  if (!solved)
    return result;
  // Refused (a sticking contact outside its cone, a sliding one pulled or slipping along its
  // friction, a separated contact closing, a residual above the tolerance): the candidate
  // projected onto the cones is the iterative solver's start, with G^T p and the patch
  // products updated by the projection's change.
  for (int k = 0; k < n && n_outside > 0; ++k) {
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
