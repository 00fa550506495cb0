#include "contact/contact_solver.h"

#include "contact/coulomb_cone.h"
#include "contact/dense_kernels.h"
#include "contact/local_contact_solve.h"

#include <cmath>
#include <sstream>
#include <stdexcept>

namespace plantar::contact {

void ContactSolver::resize(int max_contacts, int rigid_rank) {
  if (max_contacts < 0 || rigid_rank < 0) {
    std::ostringstream msg;
    msg << "ContactSolver::resize: max_contacts = " << max_contacts
        << ", rigid_rank = " << rigid_rank << ", both must be >= 0";
    throw std::invalid_argument(msg.str());
  }
  max_contacts_ = max_contacts;
  rigid_rank_ = rigid_rank;
  const int n3 = 3 * max_contacts;
  velocity_.setZero(n3);
  rigid_work_.setZero(rigid_rank);
  rigid_work2_.setZero(rigid_rank);
  de_saxce_.setZero(max_contacts);
  diag_blocks_.setZero(3, n3);
  diag_inverses_.setZero(3, n3);
  has_inverse_.setZero(max_contacts);
  eta_.setZero(max_contacts);
  contact_residual_.setZero(max_contacts);
  patch_of_.setConstant(max_contacts, -1);
  patch_velocity_.setZero(n3);
  projection_change_.setZero(n3);
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
  x_.setZero(n3);
  z_.setZero(n3);
  z_prev_.setZero(n3);
  dual_.setZero(n3);
  rhs_.setZero(n3);
  tmp_.setZero(n3);
  patch_factor_.setZero(n3, n3);
  patch_copy_.setZero(n3, n3);
  cached_first_.setConstant(max_contacts, -1);
  cached_size_.setConstant(max_contacts, -1);
  n_cached_patches_ = -1;
  cached_shift_ = -1.0;
  last_rho_ = 0.0;
  n_patch_factorizations_ = 0;
  low_rank_.setZero(n3, rigid_rank);
  capacitance_.setZero(rigid_rank, rigid_rank);
}

void ContactSolver::prepare(const ContactProblem& problem) {
  const int n = problem.n_contacts;
  patch_of_.head(n).setConstant(-1);
  for (std::size_t j = 0; j < problem.patches.size(); ++j) {
    const CompliantPatch& patch = problem.patches[j];
    patch_of_.segment(patch.first_contact, patch.n_contacts).setConstant(static_cast<int>(j));
  }
  // The blocks W_kk only for Gauss-Seidel (its local solves); here their traces.
  problem.diagonal_traces(eta_);
  double trace_sum = 0.0;
  for (int k = 0; k < n; ++k) {
    const double trace = eta_[k];
    eta_[k] = trace > 0.0 ? 3.0 / trace : 1.0;
    trace_sum += trace;
  }
  mean_diagonal_ = (n > 0 && trace_sum > 0.0) ? trace_sum / (3.0 * n) : 1.0;
}

double ContactSolver::residual(const ContactProblem& problem,
                               const Eigen::Ref<const Eigen::VectorXd>& p,
                               const Eigen::Ref<const Eigen::VectorXd>& v) {
  return contact_residuals(problem.n_contacts, p.data(), v.data(), problem.normal_bias.data(),
                           problem.friction.data(), eta_.data(), contact_residual_.data());
}

double ContactSolver::complementarity_residual(const ContactProblem& problem,
                                               const Eigen::Ref<const Eigen::VectorXd>& p,
                                               const Eigen::Ref<const Eigen::VectorXd>& v) {
  double worst = 0.0;
  for (int k = 0; k < problem.n_contacts; ++k) {
    const double trace = problem.diagonal_block(k).trace();
    const double eta = trace > 0.0 ? 3.0 / trace : 1.0;
    const double r = contact_residual(p.segment<3>(3 * k), v.segment<3>(3 * k),
                                      problem.normal_bias[k], problem.friction[k], eta);
    if (!(r <= worst))
      worst = r;
  }
  return worst;
}

void ContactSolver::compute_velocity(const ContactProblem& problem,
                                     const Eigen::Ref<const Eigen::VectorXd>& p) {
  const int n3 = 3 * problem.n_contacts;
  problem.apply_delassus(p, rigid_work_, velocity_);
  velocity_.head(n3) += problem.free_velocity.head(n3);
}

void ContactSolver::compute_patch_product(const CompliantPatch& patch,
                                          const Eigen::Ref<const Eigen::VectorXd>& p) {
  const int first = 3 * patch.first_contact, size = 3 * patch.n_contacts;
  auto out = patch_velocity_.segment(first, size);
  out.setZero();
  for (int j = 0; j < size; j += 3) {
    const Eigen::Vector3d p_patch = patch.rotation.transpose() * p.segment<3>(first + j);
    add_three_columns(patch.compliance_over_dt.col(j).data(),
                      patch.compliance_over_dt.outerStride(), size, p_patch.data(), out.data());
  }
}

void ContactSolver::add_patch_velocities(const ContactProblem& problem) {
  for (const CompliantPatch& patch : problem.patches) {
    const int first = 3 * patch.first_contact, size = 3 * patch.n_contacts;
    for (int i = first; i < first + size; i += 3)
      velocity_.segment<3>(i).noalias() += patch.rotation * patch_velocity_.segment<3>(i);
  }
}

SolverResult ContactSolver::solve(const ContactProblem& problem, const SolverSettings& settings,
                                  Eigen::Ref<Eigen::VectorXd> impulses) {
  settings.validate();
  const int n = problem.n_contacts;
  if (n > max_contacts_ || problem.rigid_rank() != rigid_rank_ || impulses.size() < 3 * n) {
    std::ostringstream msg;
    msg << "ContactSolver::solve: problem has n_contacts = " << n << ", rigid rank "
        << problem.rigid_rank() << ", impulses size " << impulses.size()
        << "; workspace sized for max_contacts = " << max_contacts_ << ", rigid rank "
        << rigid_rank_ << " (call resize)";
    throw std::invalid_argument(msg.str());
  }
  problem.validate(/*check_matrices=*/false); // non-finite W shows as SolverStatus::non_finite
  SolverResult result;
  history_size_ = 0;
  if (n == 0) {
    result.status = SolverStatus::converged;
    return result;
  }
  prepare(problem);
  if (!settings.warm_start)
    impulses.head(3 * n).setZero();
  for (int k = 0; k < n; ++k) {
    const Eigen::Vector3d p = impulses.segment<3>(3 * k);
    const Eigen::Vector3d projected =
        p.allFinite() ? project_onto_cone(p, problem.friction[k]) : Eigen::Vector3d::Zero();
    impulses.segment<3>(3 * k) = projected;
    // A caller's warm product is of the unprojected impulses: corrected by this change.
    projection_change_.segment<3>(3 * k) = projected - p;
    if (!p.allFinite())
      projection_change_.segment<3>(3 * k).setConstant(std::nan(""));
  }
  warm_products_usable_ = settings.warm_start;
  start_ready_ = false;
  if (settings.sticking_direct && settings.warm_start &&
      solve_sticking(problem, settings, impulses, result))
    return result;
  const DirectAttempt attempt = result.direct_attempt;
  if (settings.solver == ContactSolverType::gauss_seidel)
    result = solve_gauss_seidel(problem, settings, impulses);
  else {
    result = solve_admm(problem, settings, impulses);
    for (const CompliantPatch& patch : problem.patches) // for patch_product()
      compute_patch_product(patch, impulses);
  }
  result.direct_attempt = attempt;
  if (!impulses.head(3 * n).allFinite() || !std::isfinite(result.residual)) {
    result.status = SolverStatus::non_finite;
    impulses.head(3 * n).setZero();
  }
  return result;
}

} // namespace plantar::contact
