#include "contact/solver_settings.h"

#include <cmath>
#include <sstream>
#include <stdexcept>

namespace plantar::contact {

namespace {
template <typename T> [[noreturn]] void bad(const char* name, T value, const char* range) {
  std::ostringstream msg;
  msg << "SolverSettings." << name << " = " << value << ", allowed " << range;
  throw std::invalid_argument(msg.str());
}
} // namespace

void SolverSettings::validate() const {
  if (!(tolerance > 0.0) || !std::isfinite(tolerance))
    bad("tolerance", tolerance, "(0, inf)");
  if (max_iterations < 1)
    bad("max_iterations", max_iterations, "[1, inf)");
  if (!(sweep_skip >= 0.0 && sweep_skip < 1.0))
    bad("sweep_skip", sweep_skip, "[0, 1)");
  if (!(rho_scale > 0.0) || !std::isfinite(rho_scale))
    bad("rho_scale", rho_scale, "(0, inf)");
  if (!(proximal_scale >= 0.0) || !std::isfinite(proximal_scale))
    bad("proximal_scale", proximal_scale, "[0, inf)");
  if (rho_update_interval < 1)
    bad("rho_update_interval", rho_update_interval, "[1, inf)");
  if (!(rho_update_ratio > 1.0))
    bad("rho_update_ratio", rho_update_ratio, "(1, inf)");
  if (max_factorizations < 1)
    bad("max_factorizations", max_factorizations, "[1, inf)");
  if (auto_check_interval < 1)
    bad("auto_check_interval", auto_check_interval, "[1, inf)");
  if (!(auto_switch_sweeps >= 1.0))
    bad("auto_switch_sweeps", auto_switch_sweeps, "[1, inf)");
  if (!(auto_newton_iterations >= 1.0))
    bad("auto_newton_iterations", auto_newton_iterations, "[1, inf)");
  if (newton_stall_iterations < 0)
    bad("newton_stall_iterations", newton_stall_iterations, "[0, inf)");
  if (!(newton_rho_scale > 0.0) || !std::isfinite(newton_rho_scale))
    bad("newton_rho_scale", newton_rho_scale, "(0, inf)");
  if (auto_newton_stall_iterations < 0)
    bad("auto_newton_stall_iterations", auto_newton_stall_iterations, "[0, inf)");
}

const char* to_string(SolverStatus status) {
  switch (status) {
  case SolverStatus::converged:
    return "converged";
  case SolverStatus::max_iterations:
    return "max_iterations";
  case SolverStatus::non_finite:
    return "non_finite";
  }
  return "unknown";
}

const char* to_string(DirectAttempt attempt) {
  switch (attempt) {
  case DirectAttempt::not_tried:
    return "not_tried";
  case DirectAttempt::accepted:
    return "accepted";
  case DirectAttempt::refused_cone:
    return "refused_cone";
  case DirectAttempt::refused_residual:
    return "refused_residual";
  case DirectAttempt::failed:
    return "failed";
  }
  return "unknown";
}

const char* to_string(ContactSolverType type) {
  switch (type) {
  case ContactSolverType::gauss_seidel:
    return "gauss_seidel";
  case ContactSolverType::admm:
    return "admm";
  case ContactSolverType::newton:
    return "newton";
  case ContactSolverType::automatic:
    return "auto";
  }
  return "unknown";
}

const char* to_string(SwitchReason reason) {
  switch (reason) {
  case SwitchReason::none:
    return "none";
  case SwitchReason::slow:
    return "slow";
  case SwitchReason::stalled:
    return "stalled";
  case SwitchReason::budget:
    return "budget";
  case SwitchReason::failed:
    return "failed";
  }
  return "unknown";
}

const char* to_string(NewtonLinearSolve solve) {
  switch (solve) {
  case NewtonLinearSolve::automatic:
    return "auto";
  case NewtonLinearSolve::dense:
    return "dense";
  case NewtonLinearSolve::sparse:
    return "sparse";
  case NewtonLinearSolve::woodbury:
    return "woodbury";
  }
  return "unknown";
}

void throw_if_not_converged(const SolverResult& result, const SolverSettings& settings,
                            const std::string& context) {
  if (result.converged())
    return;
  std::ostringstream msg;
  msg << context << ": contact solver " << to_string(settings.solver);
  if (settings.solver == ContactSolverType::automatic)
    msg << " (finished by " << to_string(result.finished_by) << ", switch "
        << to_string(result.switch_reason) << ")";
  msg << " " << to_string(result.status) << " after " << result.iterations
      << " iterations, residual " << result.residual << " m/s > tolerance " << settings.tolerance
      << " m/s";
  if (result.n_nonunique_local > 0 || result.n_failed_local > 0)
    msg << " (" << result.n_nonunique_local << " contacts with non-unique and "
        << result.n_failed_local << " with no local solution)";
  throw std::runtime_error(msg.str());
}

} // namespace plantar::contact
