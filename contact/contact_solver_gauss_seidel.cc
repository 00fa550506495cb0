// Nonsmooth Gauss-Seidel part of ContactSolver (see contact_solver.h).
#include "contact/contact_solver.h"
#include "contact/local_contact_solve.h"

#include "contact/coulomb_cone.h"
#include "contact/dense_kernels.h"
#include "contact/impulse_change.h"

#include <type_traits>

namespace plantar::contact {

namespace {
// W_kk and, when invertible, W_kk^-1 of contact k (outside the sweep's loop: a cold path).
__attribute__((noinline)) void build_diagonal(const ContactProblem& problem, int k,
                                              Eigen::MatrixXd& blocks, Eigen::MatrixXd& inverses,
                                              Eigen::VectorXi& has_inverse) {
  blocks.middleCols<3>(3 * k) = problem.diagonal_block(k);
  Eigen::Matrix3d inverse;
  has_inverse[k] = local_inverse(blocks.middleCols<3>(3 * k), inverse) ? 1 : 0;
  if (has_inverse[k])
    inverses.middleCols<3>(3 * k) = inverse;
}
} // namespace

void ContactSolver::start_iteration(const ContactProblem& problem,
                                    const Eigen::Ref<const Eigen::VectorXd>& p) {
  // A patch's product comes from the caller when it holds it (warm_product), corrected by the
  // cone projection's change of the warm start.
  const int n3 = 3 * problem.n_contacts;
  const int m = rigid_rank_;
  rigid_work_.head(m).noalias() = problem.rigid_factor.topRows(n3).transpose() * p.head(n3);
  patch_velocity_.head(n3).setZero();
  for (const CompliantPatch& patch : problem.patches) {
    const int first = 3 * patch.first_contact, size = 3 * patch.n_contacts;
    if (patch.warm_product_valid && warm_products_usable_) {
      patch_velocity_.segment(first, size) = patch.warm_product.head(size);
      for (int i = first; i < first + size; i += 3) { // the projection's change of p
        const Eigen::Vector3d change = projection_change_.segment<3>(i);
        if (!change.allFinite()) {
          compute_patch_product(patch, p);
          break;
        }
        if (change.squaredNorm() > 0.0) {
          const Eigen::Vector3d change_patch = patch.rotation.transpose() * change;
          add_three_columns(patch.compliance_over_dt.col(i - first).data(),
                            patch.compliance_over_dt.outerStride(), size, change_patch.data(),
                            patch_velocity_.data() + first);
        }
      }
    } else {
      compute_patch_product(patch, p);
    }
  }
  start_ready_ = true;
}

SolverResult ContactSolver::solve_gauss_seidel(const ContactProblem& problem,
                                               const SolverSettings& settings,
                                               Eigen::Ref<Eigen::VectorXd> p) {
  const int n = problem.n_contacts;
  const int n3 = 3 * n;
  const int m = rigid_rank_;
  auto g = problem.rigid_factor.topRows(n3);
  SolverResult result;
  const LocalSearch search =
      settings.enumerate_local_solutions ? LocalSearch::all : LocalSearch::first;
  // W_kk and W_kk^-1 (the sticking candidates of local solves). From the direct solve's refused
  // candidate with the sweep skip, most contacts are never solved: each is built at its first
  // local solve (has_inverse_ -1 before; damped walk 29.6-30.4 -> 28.0-28.1 us per solve).
  // Otherwise nearly all are solved in the first sweep: all are built first and loaded at the
  // top of the sweep (building at first need cost 4 % there, 64.1-65.3 against 61.4-62.7 us).
  // The same start is also where sweeps are listed: a sweep solves only the contacts whose
  // residual at the last check was above the skip, in order, with no residual at their turn.
  const bool listed = settings.sweep_skip > 0.0 && start_ready_;
  if (listed)
    has_inverse_.head(n).setConstant(-1);
  else
    for (int k = 0; k < n; ++k)
      build_diagonal(problem, k, diag_blocks_, diag_inverses_, has_inverse_);
  // y = G^T p and the patch velocities C_j (I (x) R_j)^T p (patch frames), kept current
  // through the sweeps; set by start_iteration() or by the direct solve's refused candidate.
  if (!start_ready_)
    start_iteration(problem, p);
  const double skip = settings.sweep_skip * settings.tolerance;
  // Velocities and residuals of the current impulses (from the incremental state); the
  // residual of each contact is kept in contact_residual_.
  auto check = [&]() {
    velocity_.head(n3).noalias() = g * rigid_work_.head(m);
    velocity_.head(n3) += problem.free_velocity.head(n3);
    add_patch_velocities(problem);
    return residual(problem, p, velocity_);
  };
  if (listed) { // the start's residuals, for the first sweep's list
    result.residual = check();
    if (result.residual <= settings.tolerance) {
      result.status = SolverStatus::converged;
      return result;
    }
  }
  for (int sweep = 1; sweep <= settings.max_iterations; ++sweep) {
    // Every 50 sweeps, recompute y and the patch velocities from scratch to
    // limit the round-off drift of the incremental updates.
    if (sweep % 50 == 0) {
      rigid_work_.head(m).noalias() = g.transpose() * p.head(n3);
      for (const CompliantPatch& patch : problem.patches)
        compute_patch_product(patch, p);
    }
    result.n_nonunique_local = 0;
    result.n_failed_local = 0;
    // One sweep; kListed: only the contacts above the skip at the last check, W_kk built at
    // first need.
    auto sweep_contacts = [&](auto listed_sweep) {
      constexpr bool kListed = decltype(listed_sweep)::value;
      for (int k = 0; k < n; ++k) {
        if constexpr (kListed) {
          if (contact_residual_[k] <= skip)
            continue;
        }
        Eigen::Matrix3d block, inverse;
        if constexpr (!kListed) {
          block = diag_blocks_.middleCols<3>(3 * k);
          inverse = diag_inverses_.middleCols<3>(3 * k);
        }
        const Eigen::Vector3d p_old = p.segment<3>(3 * k);
        const int j = patch_of_[k];
        Eigen::Vector3d v_k = problem.free_velocity.segment<3>(3 * k);
        if (j >= 0)
          v_k.noalias() += problem.patches[j].rotation * patch_velocity_.segment<3>(3 * k);
        for (int c = 0; c < m; ++c) { // G_k y
          const double* g_c = problem.rigid_factor.col(c).data() + 3 * k;
          const double y_c = rigid_work_[c];
          v_k[0] += g_c[0] * y_c;
          v_k[1] += g_c[1] * y_c;
          v_k[2] += g_c[2] * y_c;
        }
        if (!kListed && skip > 0.0 &&
            contact_residual(p_old, v_k, problem.normal_bias[k], problem.friction[k], eta_[k]) <=
                skip)
          continue; // close enough: left for this sweep
        if constexpr (kListed) {
          if (has_inverse_[k] < 0)
            build_diagonal(problem, k, diag_blocks_, diag_inverses_, has_inverse_);
          block = diag_blocks_.middleCols<3>(3 * k);
          inverse = diag_inverses_.middleCols<3>(3 * k);
        }
        const Eigen::Vector3d q = v_k - block * p_old;
        const LocalSolution local =
            solve_local_contact(block, q, problem.normal_bias[k], problem.friction[k], p_old,
                                search, has_inverse_[k] ? &inverse : nullptr);
        ++result.n_local_solves;
        Eigen::Vector3d p_new;
        if (local.n_solutions > 0) {
          p_new = local.impulse;
          if (local.n_solutions > 1)
            ++result.n_nonunique_local;
        } else {
          // No exact local solution (singular block): projected step.
          ++result.n_failed_local;
          p_new = project_onto_cone(
              p_old - eta_[k] * de_saxce_velocity(v_k, problem.normal_bias[k], problem.friction[k]),
              problem.friction[k]);
        }
        const Eigen::Vector3d delta = p_new - p_old;
        if (delta.squaredNorm() == 0.0)
          continue;
        p.segment<3>(3 * k) = p_new;
        add_impulse_change(problem, j >= 0 ? &problem.patches[j] : nullptr, k, delta,
                           rigid_work_.data(), patch_velocity_.data());
      }
    };
    if (listed)
      sweep_contacts(std::true_type{});
    else
      sweep_contacts(std::false_type{});
    result.iterations = sweep;
    result.residual = check();
    record(sweep, result.residual);
    if (!std::isfinite(result.residual)) {
      result.status = SolverStatus::non_finite;
      return result;
    }
    if (result.residual <= settings.tolerance) {
      result.status = SolverStatus::converged;
      break;
    }
  }
  // After 50 or more sweeps, the final residual from a fresh product (bounds the round-off of
  // the incremental updates; below that the sweep's velocities are used, saving a pass over W).
  if (result.iterations >= 50) {
    compute_velocity(problem, p);
    result.residual = residual(problem, p, velocity_);
  }
  if (!std::isfinite(result.residual))
    result.status = SolverStatus::non_finite;
  else
    result.status = result.residual <= settings.tolerance ? SolverStatus::converged
                                                          : SolverStatus::max_iterations;
  return result;
}

} // namespace plantar::contact
