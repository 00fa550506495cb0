// Direct solve on the warm start's active set for rigid contacts (rigid_sticking_solver.h).
#include "contact/rigid_sticking_solver.h"

#include "contact/semidefinite_cholesky.h"

#include <Eigen/Cholesky>
#include <cmath>

namespace plantar::contact {

namespace {
constexpr int kMaxRounds = 16; // active sets tried in one solve
constexpr int kMaxPulls = 2;   // a contact pulled this often is not re-added by closing

// The nonzero columns of the semi-definite Cholesky factor of @p a (s x s, overwritten; pivots
// at or below 1e-10 of the largest diagonal entry dropped) into the first k columns of @p out
// (s x s). Returns k.
int semidefinite_columns(Eigen::Ref<Eigen::MatrixXd> a, Eigen::Ref<Eigen::MatrixXd> out) {
  semidefinite_cholesky(a, 1e-10);
  const int s = static_cast<int>(a.rows());
  int k = 0;
  for (int j = 0; j < s; ++j) {
    if (a(j, j) == 0.0)
      continue;
    out.col(k).head(j).setZero();
    out.col(k).tail(s - j) = a.col(j).tail(s - j);
    ++k;
  }
  return k;
}

// x <- (F^T F)^-1 x for the Cholesky factor @p chol of F^T F.
template <typename Chol, typename Vector> void solve_gram(const Chol& chol, Vector&& x) {
  chol.solveInPlace(x);
  chol.transpose().solveInPlace(x);
}
} // namespace

void RigidStickingSolver::resize(int max_contacts, int rigid_rank) {
  max_contacts_ = max_contacts;
  rigid_rank_ = rigid_rank;
  const int rows = 3 * max_contacts, m = rigid_rank;
  state_.setZero(max_contacts);
  pulls_.setZero(max_contacts);
  direction_.setZero(2 * max_contacts);
  equations_.setZero(rows, m);
  columns_.setZero(rows, m);
  equations_factor_.setZero(rows, m);
  gram_.setZero(m, m);
  factor_.setZero(m, m);
  inner_.setZero(m, m);
  reduced_.setZero(m, m);
  reduced_factor_.setZero(m, m);
  reduced_inner_.setZero(m, m);
  residual_.setZero(rows);
  correction_.setZero(rows);
  change_.setZero(rows);
  candidate_.setZero(rows);
  new_impulses_.setZero(rows);
  warm_rigid_.setZero(m);
  rigid_change_.setZero(m);
  u_.setZero(m);
  work_.setZero(m);
  work2_.setZero(m);
  z_work_.setZero(m);
}

Eigen::Vector3d RigidStickingSolver::held_direction(const ContactProblem& problem, int k) const {
  return Eigen::Vector3d(1.0, problem.friction[k] * direction_[2 * k],
                         problem.friction[k] * direction_[2 * k + 1]);
}

SolverResult RigidStickingSolver::solve(const ContactProblem& problem,
                                        const SolverSettings& settings,
                                        Eigen::Ref<Eigen::VectorXd> impulses,
                                        DelassusProducts& products) {
  const int n = problem.n_contacts;
  const int n3 = 3 * n;
  const int m = rigid_rank_;
  SolverResult result;
  for (const CompliantPatch& patch : problem.patches)
    if (patch.n_contacts > 0)
      return result; // compliant contacts: StickingSolver's
  if (!problem.general.empty() || m == 0 || n > max_contacts_)
    return result;
  // The warm start's prediction: every contact with p_n > 0 sticks (its three rows unknown).
  auto candidate = candidate_.head(n3);
  int n_rows = 0;
  for (int k = 0; k < n; ++k) {
    state_[k] = impulses[3 * k] > 0.0 ? kSticking : kSeparated;
    pulls_[k] = 0;
    n_rows += state_[k] == kSticking ? 3 : 0;
    candidate.segment<3>(3 * k) = state_[k] == kSticking
                                      ? Eigen::Vector3d(impulses.segment<3>(3 * k))
                                      : Eigen::Vector3d::Zero();
  }
  const bool cold = n_rows == 0;
  for (int k = 0; k < n && cold; ++k) // no warm start: the contacts closing under v_free
    if (problem.free_velocity[3 * k] + problem.normal_bias[k] < -settings.tolerance) {
      state_[k] = kSticking;
      n_rows += 3;
    }
  if (n_rows == 0)
    return result;

  const auto g = problem.rigid_factor.topRows(n3);
  auto rigid = products.rigid.head(m);
  auto warm_rigid = warm_rigid_.head(m);
  for (int round = 0;; ++round) {
    if (n_rows == 0 || round == kMaxRounds) {
      result.direct_attempt = DirectAttempt::refused_cone;
      return result;
    }
    // Equation rows B (the velocity rows set to zero) and impulse rows C (w^T of each unknown's
    // impulse direction) over the unknowns U, and r = -(v_free + b e_n + G G^T p0)_B.
    warm_rigid.noalias() = g.transpose() * candidate;
    auto b = equations_.topRows(n_rows);
    auto c = columns_.topRows(n_rows);
    auto r = residual_.head(n_rows);
    for (int k = 0, a = 0; k < n; ++k) {
      if (state_[k] == kSticking) {
        b.middleRows<3>(a) = g.middleRows<3>(3 * k);
        c.middleRows<3>(a) = g.middleRows<3>(3 * k);
        r.segment<3>(a) = problem.free_velocity.segment<3>(3 * k);
        r[a] += problem.normal_bias[k];
        a += 3;
      } else if (state_[k] == kNormal) {
        b.row(a) = g.row(3 * k);
        c.row(a).noalias() = held_direction(problem, k).transpose() * g.middleRows<3>(3 * k);
        r[a] = problem.free_velocity[3 * k] + problem.normal_bias[k];
        ++a;
      }
    }
    r.noalias() += b * warm_rigid;
    r = -r;
    // z = G^T dp = L u over range(C^T) (C^T C = L L^T, L m x k), u = (B L)^+ r (least squares,
    // minimum norm: (B L)^T B L = L2 L2^T, L2 k x k2); dp = C L T^-1 u (T = L^T L): the
    // impulse change of least norm with C^T dp = z.
    // (B L)^T B L is factored with the pivot threshold also when B = C (then it is T^2): the
    // shortcut T^-2 by T's plain Cholesky let T's near-singular directions into the solution
    // (it changed the stabilized compliant-ankle walk's peak waist acceleration 3.8 -> 20 m/s^2).
    gram_.noalias() = c.transpose() * c;
    const int k = semidefinite_columns(gram_, factor_);
    auto inner = inner_.topLeftCorner(k, k);
    const auto l = factor_.leftCols(k);
    inner.noalias() = l.transpose() * l;
    auto bl = equations_factor_.topLeftCorner(n_rows, k);
    bl.noalias() = b * l;
    auto reduced = reduced_.topLeftCorner(k, k);
    reduced.noalias() = bl.transpose() * bl;
    const int k2 = semidefinite_columns(reduced, reduced_factor_.topLeftCorner(k, k));
    auto reduced_inner = reduced_inner_.topLeftCorner(k2, k2);
    const auto l2 = reduced_factor_.topLeftCorner(k, k2);
    reduced_inner.noalias() = l2.transpose() * l2;
    if (k == 0 || k2 == 0 ||
        Eigen::internal::llt_inplace<double, Eigen::Lower>::unblocked(inner) >= 0 ||
        Eigen::internal::llt_inplace<double, Eigen::Lower>::unblocked(reduced_inner) >= 0) {
      result.direct_attempt = DirectAttempt::failed;
      return result;
    }
    const auto chol = inner.triangularView<Eigen::Lower>();
    const auto chol2 = reduced_inner.triangularView<Eigen::Lower>();
    // u by the factors, then once more for the equations' residual (iterative refinement)
    // unless the rows' velocity error is already below tolerance / 100.
    auto u = u_.head(k);
    auto z = rigid_change_.head(m);
    auto e = correction_.head(n_rows);
    u.setZero();
    e = r;
    for (int pass = 0; pass < 2; ++pass) {
      auto q = work_.head(k);
      auto q2 = work2_.head(k2);
      q.noalias() = bl.transpose() * e;
      q2.noalias() = l2.transpose() * q;
      solve_gram(chol2, q2);
      solve_gram(chol2, q2);
      u.noalias() += l2 * q2; // (B L)^+ e = L2 T2^-2 L2^T (B L)^T e
      z.noalias() = l * u;
      e = r;
      e.noalias() -= b * z;
      if (!(e.cwiseAbs().maxCoeff() > 0.01 * settings.tolerance))
        break;
    }
    auto t = work_.head(k);
    t = u;
    solve_gram(chol, t);
    auto dp = change_.head(n_rows);
    auto lt = z_work_.head(m);
    lt.noalias() = l * t;
    dp.noalias() = c * lt;
    rigid = warm_rigid + z;
    // Each contact's new impulse. Friction first: a sticking contact outside its cone by
    // friction (p_n >= 0) keeps its normal row, its impulse held on the cone in its tangential
    // direction. Only when none is, a pulled contact (p_n < 0) separates: pulls seen while
    // friction is still off are often spurious.
    int n_friction = 0, n_pulled = 0;
    for (int j = 0, a = 0; j < n; ++j) {
      if (state_[j] == kSticking) {
        new_impulses_.segment<3>(3 * j) = candidate.segment<3>(3 * j) + dp.segment<3>(a);
        a += 3;
      } else if (state_[j] == kNormal) {
        new_impulses_.segment<3>(3 * j) =
            candidate.segment<3>(3 * j) + dp[a] * held_direction(problem, j);
        ++a;
      } else {
        continue;
      }
      const Eigen::Vector3d p = new_impulses_.segment<3>(3 * j);
      if (!(p[0] >= 0.0))
        ++n_pulled;
      else if (state_[j] == kSticking && std::hypot(p[1], p[2]) > problem.friction[j] * p[0])
        ++n_friction;
    }
    for (int j = 0; j < n && n_friction + n_pulled > 0; ++j) {
      if (state_[j] != kSticking && state_[j] != kNormal)
        continue;
      const Eigen::Vector3d p = new_impulses_.segment<3>(3 * j);
      const double tangential = std::hypot(p[1], p[2]);
      if (n_friction > 0 && state_[j] == kSticking && p[0] >= 0.0 &&
          tangential > problem.friction[j] * p[0]) {
        n_rows -= 2;
        state_[j] = kNormal;
        direction_.segment<2>(2 * j) = p.tail<2>() / tangential;
        candidate.segment<3>(3 * j) = impulses[3 * j] * held_direction(problem, j);
      } else if (n_friction == 0 && !(p[0] >= 0.0)) {
        n_rows -= state_[j] == kSticking ? 3 : 1;
        state_[j] = kPulled;
        ++pulls_[j];
        candidate.segment<3>(3 * j).setZero();
      }
    }
    if (n_friction + n_pulled > 0)
      continue;
    // All in their cones: a separated contact closing (v_n + b < -tolerance) joins the sticking
    // ones; a held one that slips has its impulse turned against the slip, when the turn's
    // natural-map residual (|dp_t| / eta_k) is above a tenth of the tolerance.
    int n_changed = 0;
    for (int j = 0; j < n; ++j) {
      if (state_[j] == kSticking || (state_[j] == kPulled && pulls_[j] >= kMaxPulls))
        continue;
      if (state_[j] == kSeparated || state_[j] == kPulled) {
        const double closing =
            g.row(3 * j).dot(rigid) + problem.free_velocity[3 * j] + problem.normal_bias[j];
        if (closing < -settings.tolerance) {
          // Slipping (|v_t| > tolerance), it joins held against its slip.
          const Eigen::Vector2d slip =
              g.middleRows<2>(3 * j + 1) * rigid + problem.free_velocity.segment<2>(3 * j + 1);
          const double speed = slip.norm();
          state_[j] = speed > settings.tolerance ? kNormal : kSticking;
          n_rows += state_[j] == kNormal ? 1 : 3;
          if (state_[j] == kNormal)
            direction_.segment<2>(2 * j) = -slip / speed;
          ++n_changed;
        }
        continue;
      }
      const Eigen::Vector2d slip =
          g.middleRows<2>(3 * j + 1) * rigid + problem.free_velocity.segment<2>(3 * j + 1);
      const double speed = slip.norm();
      if (speed <= settings.tolerance)
        continue;
      const Eigen::Vector2d turned = -slip / speed;
      const double p_n = new_impulses_[3 * j];
      if (problem.friction[j] * p_n * (turned - direction_.segment<2>(2 * j)).norm() >
          0.1 * settings.tolerance * products.eta[j]) {
        direction_.segment<2>(2 * j) = turned;
        candidate.segment<3>(3 * j) = impulses[3 * j] * held_direction(problem, j);
        ++n_changed;
      }
    }
    if (n_changed == 0)
      break;
  }
  for (int j = 0; j < n; ++j)
    if (state_[j] == kSticking || state_[j] == kNormal)
      candidate.segment<3>(3 * j) = new_impulses_.segment<3>(3 * j);
  if (!candidate.allFinite()) {
    result.direct_attempt = DirectAttempt::failed;
    return result;
  }
  products.velocity.head(n3).noalias() = g * rigid;
  products.velocity.head(n3) += problem.free_velocity.head(n3);
  const double residual = products.residual(problem, candidate, products.velocity);
  if (!(residual <= settings.tolerance)) {
    result.direct_attempt = DirectAttempt::refused_residual;
    return result;
  }
  impulses.head(n3) = candidate;
  result.direct = true;
  result.direct_attempt = DirectAttempt::accepted;
  result.iterations = 0;
  result.residual = residual;
  result.status = SolverStatus::converged;
  return result;
}

} // namespace plantar::contact
