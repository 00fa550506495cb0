#include "contact/gauss_seidel_solver.h"

#include "contact/coulomb_cone.h"
#include "contact/dense_kernels.h"
#include "contact/impulse_change.h"
#include "contact/local_contact_solve.h"

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

void GaussSeidelSolver::resize(int max_contacts, int rigid_rank) {
  rigid_rank_ = rigid_rank;
  diag_blocks_.setZero(3, 3 * max_contacts);
  diag_inverses_.setZero(3, 3 * max_contacts);
  has_inverse_.setZero(max_contacts);
}

void GaussSeidelSolver::start_compressed(const ContactProblem& problem, int j,
                                         const Eigen::Ref<const Eigen::VectorXd>& p) {
  const CompliantPatch& patch = problem.patches[j];
  if (compressed_.size() < problem.patches.size())
    compressed_.resize(problem.patches.size());
  HierarchicalCompliance::ProductState& state = compressed_[j];
  if (state.near.size() != 3 * patch.n_contacts)
    patch.compressed->resize_state(state);
  const int first = 3 * patch.first_contact;
  patch.compressed->start_product(
      [&](int node) -> Eigen::Vector3d {
        return patch.node_rotation(node).transpose() * p.segment<3>(first + 3 * node);
      },
      state);
}

void GaussSeidelSolver::write_compressed(const ContactProblem& problem,
                                         DelassusProducts& products) const {
  for (std::size_t j = 0; j < problem.patches.size(); ++j) {
    const CompliantPatch& patch = problem.patches[j];
    if (patch.compressed != nullptr)
      patch.compressed->write_product(
          compressed_[j],
          products.patch_product.segment(3 * patch.first_contact, 3 * patch.n_contacts),
          patch.compressed_scale);
  }
}

void GaussSeidelSolver::start_iteration(const ContactProblem& problem,
                                        const SolverSettings& settings,
                                        const Eigen::Ref<const Eigen::VectorXd>& p,
                                        DelassusProducts& products) {
  // A patch's product comes from the caller when it holds it (warm_product), corrected by the
  // cone projection's change of the warm start.
  const int n3 = 3 * problem.n_contacts;
  const int m = rigid_rank_;
  products.rigid.head(m).noalias() = problem.rigid_factor.topRows(n3).transpose() * p.head(n3);
  products.patch_product.head(n3).setZero();
  for (std::size_t index = 0; index < problem.patches.size(); ++index) {
    const CompliantPatch& patch = problem.patches[index];
    const int first = 3 * patch.first_contact, size = 3 * patch.n_contacts;
    if (patch.compressed != nullptr) {
      start_compressed(problem, static_cast<int>(index), p);
    } else if (patch.warm_product_valid && settings.warm_start) {
      products.patch_product.segment(first, size) = patch.warm_product.head(size);
      for (int i = first; i < first + size; i += 3) { // the projection's change of p
        const Eigen::Vector3d change = products.warm_change.segment<3>(i);
        if (!change.allFinite()) {
          products.compute_patch_product(patch, p);
          break;
        }
        if (change.squaredNorm() > 0.0) {
          const Eigen::Vector3d change_patch =
              patch.node_rotation((i - first) / 3).transpose() * change;
          add_three_columns(patch.compliance_over_dt.col(i - first).data(),
                            patch.compliance_over_dt.outerStride(), size, change_patch.data(),
                            products.patch_product.data() + first);
        }
      }
    } else {
      products.compute_patch_product(patch, p);
    }
  }
}

SolverResult GaussSeidelSolver::solve(const ContactProblem& problem, const SolverSettings& settings,
                                      Eigen::Ref<Eigen::VectorXd> p, DelassusProducts& products,
                                      StartProducts start, ResidualHistory& history) {
  const int n = problem.n_contacts;
  const int n3 = 3 * n;
  const int m = rigid_rank_;
  auto g = problem.rigid_factor.topRows(n3);
  SolverResult result;
  const LocalSearch search =
      settings.enumerate_local_solutions ? LocalSearch::all : LocalSearch::first;
  // W_kk and W_kk^-1 (the sticking candidates of local solves). From the direct solve's refused
  // candidate with the sweep skip, most contacts are never solved: each is built at its first
  // local solve (has_inverse_ -1 before). Otherwise nearly all are solved in the first sweep:
  // all are built first and loaded at the top of the sweep (timings in docs/contact.md).
  // The same start is also where sweeps are listed: a sweep solves only the contacts whose
  // residual at the last check was above the skip, in order, with no residual at their turn.
  const bool listed = settings.sweep_skip > 0.0 && start == StartProducts::held;
  const bool general = !problem.general.empty();
  if (listed)
    has_inverse_.head(n).setConstant(-1);
  else
    for (int k = 0; k < n; ++k)
      build_diagonal(problem, k, diag_blocks_, diag_inverses_, has_inverse_);
  // y = G^T p and the patch velocities C_j (I (x) R_j)^T p (patch frames), kept current
  // through the sweeps; set by start_iteration() or by the direct solve's refused candidate.
  if (start == StartProducts::build)
    start_iteration(problem, settings, p, products);
  const double skip = settings.sweep_skip * settings.tolerance;
  // Velocities and residuals of the current impulses (from the incremental state); the
  // residual of each contact is kept in contact_residual_.
  auto check = [&]() {
    products.velocity.head(n3).noalias() = g * products.rigid.head(m);
    products.velocity.head(n3) += problem.free_velocity.head(n3);
    write_compressed(problem, products);
    products.add_patch_velocities(problem);
    if (general)
      problem.general.add_product(p, products.velocity);
    return products.residual(problem, p, products.velocity);
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
      products.rigid.head(m).noalias() = g.transpose() * p.head(n3);
      for (std::size_t j = 0; j < problem.patches.size(); ++j)
        if (problem.patches[j].compressed != nullptr)
          start_compressed(problem, static_cast<int>(j), p);
        else
          products.compute_patch_product(problem.patches[j], p);
    }
    result.n_nonunique_local = 0;
    result.n_failed_local = 0;
    // One sweep; kListed: only the contacts above the skip at the last check, W_kk built at
    // first need.
    auto sweep_contacts = [&](auto listed_sweep) {
      constexpr bool kListed = decltype(listed_sweep)::value;
      for (int k = 0; k < n; ++k) {
        if constexpr (kListed) {
          if (products.contact_residual[k] <= skip)
            continue;
        }
        Eigen::Matrix3d block, inverse;
        if constexpr (!kListed) {
          block = diag_blocks_.middleCols<3>(3 * k);
          inverse = diag_inverses_.middleCols<3>(3 * k);
        }
        const Eigen::Vector3d p_old = p.segment<3>(3 * k);
        const int j = products.patch_of[k];
        Eigen::Vector3d v_k = problem.free_velocity.segment<3>(3 * k);
        const CompliantPatch* patch = j >= 0 ? &problem.patches[j] : nullptr;
        const bool compressed = patch != nullptr && patch->compressed != nullptr;
        if (compressed)
          v_k.noalias() +=
              patch->node_rotation(k - patch->first_contact) *
              (patch->compressed_scale *
               patch->compressed->node_product(k - patch->first_contact, compressed_[j]));
        else if (j >= 0)
          v_k.noalias() += patch->node_rotation(k - patch->first_contact) *
                           products.patch_product.segment<3>(3 * k);
        for (int c = 0; c < m; ++c) { // G_k y
          const double* g_c = problem.rigid_factor.col(c).data() + 3 * k;
          const double y_c = products.rigid[c];
          v_k[0] += g_c[0] * y_c;
          v_k[1] += g_c[1] * y_c;
          v_k[2] += g_c[2] * y_c;
        }
        if (general) // W_gen,k: p (its rows: no kept state)
          v_k += problem.general.contact_rows_times(k, p.data());
        if (!kListed && skip > 0.0 &&
            contact_residual(p_old, v_k, problem.normal_bias[k], problem.friction[k],
                             products.eta[k]) <= skip)
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
              p_old - products.eta[k] *
                          de_saxce_velocity(v_k, problem.normal_bias[k], problem.friction[k]),
              problem.friction[k]);
        }
        const Eigen::Vector3d delta = p_new - p_old;
        if (delta.squaredNorm() == 0.0)
          continue;
        p.segment<3>(3 * k) = p_new;
        add_impulse_change(problem, compressed ? nullptr : patch, k, delta, products.rigid.data(),
                           products.patch_product.data());
        if (compressed)
          patch->compressed->add_change(
              k - patch->first_contact,
              patch->node_rotation(k - patch->first_contact).transpose() * delta, compressed_[j]);
      }
    };
    if (listed)
      sweep_contacts(std::true_type{});
    else
      sweep_contacts(std::false_type{});
    result.iterations = sweep;
    result.residual = check();
    history.record(sweep, result.residual);
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
    products.compute_velocity(problem, p);
    result.residual = products.residual(problem, p, products.velocity);
  }
  if (!std::isfinite(result.residual))
    result.status = SolverStatus::non_finite;
  else
    result.status = result.residual <= settings.tolerance ? SolverStatus::converged
                                                          : SolverStatus::max_iterations;
  return result;
}

} // namespace plantar::contact
