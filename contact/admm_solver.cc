#include "contact/admm_solver.h"

#include "contact/coulomb_cone.h"

#include <Eigen/Cholesky>
#include <algorithm>
#include <cmath>

namespace plantar::contact {

namespace {
// Lower Cholesky factor in place (lower triangle), right-looking over 64 x 64
// tiles: diagonal tiles by Eigen's unblocked kernel, panel tiles by triangular
// solves, trailing tiles by 64 x 64 x 64 products. Every Eigen kernel call
// then fits its scratch under EIGEN_STACK_ALLOCATION_LIMIT, so, unlike
// Eigen's blocked LLT (heap scratch above ~100 contacts), this never
// allocates (timing against the blocked LLT in docs/contact.md).
// Returns false if the matrix is not positive definite.
template <typename Block> bool cholesky_in_place(Block&& block) {
  constexpr Eigen::Index kTile = 64;
  Eigen::Ref<Eigen::MatrixXd> a(block);
  const Eigen::Index n = a.rows();
  for (Eigen::Index k = 0; k < n; k += kTile) {
    const Eigen::Index kb = std::min(kTile, n - k);
    auto a11 = a.block(k, k, kb, kb);
    if (Eigen::internal::llt_inplace<double, Eigen::Lower>::unblocked(a11) != -1)
      return false;
    for (Eigen::Index i = k + kb; i < n; i += kTile) {
      auto a_ik = a.block(i, k, std::min(kTile, n - i), kb);
      a11.triangularView<Eigen::Lower>().transpose().solveInPlace<Eigen::OnTheRight>(a_ik);
    }
    for (Eigen::Index j = k + kb; j < n; j += kTile) {
      const Eigen::Index jb = std::min(kTile, n - j);
      const auto a_jk = a.block(j, k, jb, kb);
      for (Eigen::Index i = j; i < n; i += kTile) {
        const Eigen::Index ib = std::min(kTile, n - i);
        a.block(i, j, ib, jb).noalias() -= a.block(i, k, ib, kb) * a_jk.transpose();
      }
    }
  }
  return true;
}
} // namespace

void AdmmSolver::resize(int max_contacts, int rigid_rank) {
  rigid_rank_ = rigid_rank;
  const int n3 = 3 * max_contacts;
  x_.setZero(n3);
  z_.setZero(n3);
  z_prev_.setZero(n3);
  dual_.setZero(n3);
  rhs_.setZero(n3);
  patch_factor_.setZero(n3, n3);
  patch_copy_.setZero(n3, n3);
  low_rank_.setZero(n3, rigid_rank);
  capacitance_.setZero(rigid_rank, rigid_rank);
  rigid_work_.setZero(rigid_rank);
  de_saxce_.setZero(max_contacts);
  cached_first_.setConstant(max_contacts, -1);
  cached_size_.setConstant(max_contacts, -1);
  n_cached_patches_ = -1;
  cached_shift_ = -1.0;
  last_rho_ = 0.0;
  n_patch_factorizations_ = 0;
}

bool AdmmSolver::factorize(const ContactProblem& problem, const DelassusProducts& products,
                           double shift) {
  const int n = problem.n_contacts;
  const int n3 = 3 * n;
  const int m = rigid_rank_;
  shift_ = shift;
  auto g = problem.rigid_factor.topRows(n3);
  if (!problem.general.empty()) {
    // A general W: the symmetric part of the whole W plus shift I, factorised dense (no reuse).
    auto block = patch_factor_.topLeftCorner(n3, n3);
    problem.assemble_delassus_into(block, /*symmetric_part=*/true);
    block.diagonal().array() += shift;
    n_cached_patches_ = -1;
    ++n_patch_factorizations_;
    return cholesky_in_place(block);
  }
  // D = blockdiag(C_j/dt^2 + c I) (patches, in their frames, Cholesky in place), c I elsewhere.
  // A patch factor is reused when the shift, the range and the block equal
  // those of the last factorisation (exact comparison with a kept copy, O(n^2)).
  const int n_patches = static_cast<int>(problem.patches.size());
  bool cache_valid = shift == cached_shift_ && n_patches == n_cached_patches_;
  for (int j = 0; j < n_patches; ++j) {
    const CompliantPatch& patch = problem.patches[j];
    const int first = 3 * patch.first_contact, size = 3 * patch.n_contacts;
    if (size == 0)
      continue;
    const bool reuse = cache_valid && cached_first_[j] == first && cached_size_[j] == size &&
                       patch_copy_.block(first, first, size, size) == patch.compliance_over_dt;
    if (reuse)
      continue;
    cache_valid = false; // later patches may overlap the ranges of stale ones
    auto copy = patch_copy_.block(first, first, size, size);
    copy = patch.compliance_over_dt;
    auto block = patch_factor_.block(first, first, size, size);
    block = patch.compliance_over_dt;
    block.diagonal().array() += shift;
    cached_first_[j] = first;
    cached_size_[j] = size;
    if (!cholesky_in_place(block)) {
      n_cached_patches_ = -1;
      return false;
    }
    ++n_patch_factorizations_;
  }
  cached_shift_ = shift;
  n_cached_patches_ = n_patches;
  if (m == 0)
    return true;
  // H = D^-1 G, column by column (triangular solves, no scratch memory).
  low_rank_.topRows(n3) = g;
  for (int k = 0; k < n; ++k)
    if (products.patch_of[k] < 0)
      low_rank_.middleRows<3>(3 * k) /= shift;
  for (const CompliantPatch& patch : problem.patches) {
    const int first = 3 * patch.first_contact, size = 3 * patch.n_contacts;
    if (size == 0)
      continue;
    // D_j^-1 = A (C + c I)^-1 A^T (A = blockdiag(a_i) orthonormal).
    auto factor = patch_factor_.block(first, first, size, size);
    for (int c = 0; c < m; ++c) {
      auto column = low_rank_.col(c).segment(first, size);
      rotate_to_patch(patch, column);
      factor.triangularView<Eigen::Lower>().solveInPlace(column);
      factor.triangularView<Eigen::Lower>().transpose().solveInPlace(column);
      rotate_from_patch(patch, column);
    }
  }
  // S = I + G^T H, Cholesky in place.
  for (int j = 0; j < m; ++j)
    for (int i = j; i < m; ++i)
      capacitance_(i, j) = g.col(i).dot(low_rank_.col(j).head(n3)) + (i == j ? 1.0 : 0.0);
  return cholesky_in_place(capacitance_);
}

// x = (W + c I)^-1 rhs = D^-1 rhs - H S^-1 G^T D^-1 rhs (Woodbury).
void AdmmSolver::solve_shifted(const ContactProblem& problem, const DelassusProducts& products,
                               const Eigen::Ref<const Eigen::VectorXd>& rhs,
                               Eigen::Ref<Eigen::VectorXd> x) {
  const int n = problem.n_contacts;
  const int n3 = 3 * n;
  const int m = rigid_rank_;
  x.head(n3) = rhs.head(n3);
  if (!problem.general.empty()) {
    auto factor = patch_factor_.topLeftCorner(n3, n3);
    auto head = x.head(n3);
    factor.triangularView<Eigen::Lower>().solveInPlace(head);
    factor.triangularView<Eigen::Lower>().transpose().solveInPlace(head);
    return;
  }
  for (int k = 0; k < n; ++k)
    if (products.patch_of[k] < 0)
      x.segment<3>(3 * k) /= shift_;
  for (const CompliantPatch& patch : problem.patches) {
    const int first = 3 * patch.first_contact, size = 3 * patch.n_contacts;
    if (size == 0)
      continue;
    auto factor = patch_factor_.block(first, first, size, size);
    auto segment = x.segment(first, size);
    rotate_to_patch(patch, segment);
    factor.triangularView<Eigen::Lower>().solveInPlace(segment);
    factor.triangularView<Eigen::Lower>().transpose().solveInPlace(segment);
    rotate_from_patch(patch, segment);
  }
  if (m == 0)
    return;
  auto g = problem.rigid_factor.topRows(n3);
  rigid_work_.noalias() = g.transpose() * x.head(n3);
  capacitance_.triangularView<Eigen::Lower>().solveInPlace(rigid_work_);
  capacitance_.triangularView<Eigen::Lower>().transpose().solveInPlace(rigid_work_);
  x.head(n3).noalias() -= low_rank_.topRows(n3) * rigid_work_;
}

SolverResult AdmmSolver::solve(const ContactProblem& problem, const SolverSettings& settings,
                               Eigen::Ref<Eigen::VectorXd> p, DelassusProducts& products,
                               StartProducts /*start*/, ResidualHistory& history) {
  const int n = problem.n_contacts;
  const int n3 = 3 * n;
  SolverResult result;
  // Initial rho: the last solve's final rho if settings.warm_rho (then the
  // patch factorisations are usually reused), else rho_scale * mean diag W.
  double rho = settings.rho_scale * products.mean_diagonal;
  if (settings.warm_rho && last_rho_ > 0.0)
    rho = std::clamp(last_rho_, 1e-4 * products.mean_diagonal, 1e4 * products.mean_diagonal);
  const double eta = settings.proximal_scale * products.mean_diagonal;

  auto finish = [&](SolverStatus status) {
    result.status = status;
    result.rho = rho;
    if (status != SolverStatus::non_finite)
      last_rho_ = rho;
    for (const CompliantPatch& patch : problem.patches) // for ContactSolver::patch_product()
      products.compute_patch_product(patch, p);
    return result;
  };

  z_.head(n3) = p.head(n3);
  products.compute_velocity(problem, z_);
  result.residual = products.residual(problem, z_, products.velocity);
  if (result.residual <= settings.tolerance)
    return finish(SolverStatus::converged);
  // Dual warm start: rho u = -(De Saxce velocity) at the solution.
  for (int k = 0; k < n; ++k)
    dual_.segment<3>(3 * k) = -de_saxce_velocity(products.velocity.segment<3>(3 * k),
                                                 problem.normal_bias[k], problem.friction[k]) /
                              rho;
  // De Saxce term s_k = mu_k ||v_t,k||, frozen while the inner convex problem
  // (cone-constrained QP with fixed s) is solved to a fraction of the outer
  // residual, then refreshed: a fixed point on s around a convergent ADMM.
  for (int k = 0; k < n; ++k)
    de_saxce_[k] = problem.friction[k] *
                   std::hypot(products.velocity[3 * k + 1], products.velocity[3 * k + 2]);
  if (!factorize(problem, products, rho + eta))
    return finish(SolverStatus::non_finite);
  result.n_factorizations = 1;
  int last_update = 0;
  double residual_at_refresh = result.residual;

  for (int it = 1; it <= settings.max_iterations; ++it) {
    result.iterations = it;
    // rhs = -(v_free + (b + s) e_n) + (rho + eta) z - rho u, s frozen.
    for (int k = 0; k < n; ++k) {
      Eigen::Vector3d r = -problem.free_velocity.segment<3>(3 * k);
      r[0] -= problem.normal_bias[k] + de_saxce_[k];
      rhs_.segment<3>(3 * k) =
          r + (rho + eta) * z_.segment<3>(3 * k) - rho * dual_.segment<3>(3 * k);
    }
    // A non-symmetric general W: its skew part taken explicitly at z (the factor holds the
    // symmetric part).
    if (!problem.general.symmetric()) {
      x_.head(n3).setZero();
      problem.general.add_skew_product(z_, x_);
      rhs_.head(n3) -= x_.head(n3);
    }
    solve_shifted(problem, products, rhs_, x_);
    z_prev_.head(n3) = z_.head(n3);
    for (int k = 0; k < n; ++k)
      z_.segment<3>(3 * k) =
          project_onto_cone(x_.segment<3>(3 * k) + dual_.segment<3>(3 * k), problem.friction[k]);
    dual_.head(n3) += x_.head(n3) - z_.head(n3);
    products.compute_velocity(problem, z_);
    result.residual = products.residual(problem, z_, products.velocity);
    history.record(it, result.residual);
    if (!std::isfinite(result.residual)) {
      p.head(n3) = z_.head(n3);
      return finish(SolverStatus::non_finite);
    }
    if (result.residual <= settings.tolerance) {
      p.head(n3) = z_.head(n3);
      return finish(SolverStatus::converged);
    }
    // Residual of the inner problem (s frozen); refresh s when it is small.
    double inner = 0.0;
    for (int k = 0; k < n; ++k) {
      Eigen::Vector3d modified = products.velocity.segment<3>(3 * k);
      modified[0] += problem.normal_bias[k] + de_saxce_[k];
      const Eigen::Vector3d zk = z_.segment<3>(3 * k);
      inner = std::max(
          inner,
          (zk - project_onto_cone(zk - products.eta[k] * modified, problem.friction[k])).norm() /
              products.eta[k]);
    }
    if (inner <= 0.25 * result.residual) {
      // Damped refresh when the outer residual did not decrease (cycling).
      const double weight = result.residual < residual_at_refresh ? 1.0 : 0.5;
      residual_at_refresh = result.residual;
      for (int k = 0; k < n; ++k)
        de_saxce_[k] += weight * (problem.friction[k] * std::hypot(products.velocity[3 * k + 1],
                                                                   products.velocity[3 * k + 2]) -
                                  de_saxce_[k]);
    }
    // rho adaptation, every rho_update_interval iterations: the OSQP rule
    // rho *= sqrt(primal / dual) on normalised residuals, applied when the
    // ratio exceeds rho_update_ratio; rho stays in [1e-4, 1e4] x mean diag W.
    double factor = 1.0;
    if (it - last_update >= settings.rho_update_interval) {
      const double primal = (x_.head(n3) - z_.head(n3)).lpNorm<Eigen::Infinity>() /
                            std::max({x_.head(n3).lpNorm<Eigen::Infinity>(),
                                      z_.head(n3).lpNorm<Eigen::Infinity>(), 1e-300});
      const double dual = rho * (z_.head(n3) - z_prev_.head(n3)).lpNorm<Eigen::Infinity>() /
                          std::max({products.velocity.head(n3).lpNorm<Eigen::Infinity>(),
                                    rho * dual_.head(n3).lpNorm<Eigen::Infinity>(), 1e-300});
      const double ratio = primal / std::max(dual, 1e-300);
      if (ratio > settings.rho_update_ratio || ratio * settings.rho_update_ratio < 1.0)
        factor = std::sqrt(ratio);
      factor =
          std::clamp(rho * factor, 1e-4 * products.mean_diagonal, 1e4 * products.mean_diagonal) /
          rho;
    }
    if (factor != 1.0 && result.n_factorizations < settings.max_factorizations) {
      const double rho_new = rho * factor;
      dual_.head(n3) *= rho / rho_new;
      rho = rho_new;
      if (!factorize(problem, products, rho + eta)) {
        p.head(n3) = z_.head(n3);
        return finish(SolverStatus::non_finite);
      }
      ++result.n_factorizations;
      last_update = it;
    }
  }
  p.head(n3) = z_.head(n3);
  return finish(SolverStatus::max_iterations);
}

} // namespace plantar::contact
