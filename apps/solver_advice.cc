#include "apps/solver_advice.h"

#include <cmath>
#include <sstream>
#include <vector>

namespace plantar::app {
namespace {

/// @p value to one significant digit, rounded down (@p up false) or up.
double one_digit(double value, bool up) {
  const double scale = std::pow(10.0, std::floor(std::log10(value)));
  const double digit = up ? std::ceil(value / scale - 1e-9) : std::floor(value / scale + 1e-9);
  return digit * scale;
}

} // namespace

double stiffness_step_ratio(const SolverFailure& failure) {
  if (!(failure.foot_stiffness > 0) || !(failure.robot_mass > 0))
    return 0;
  return failure.time_step * std::sqrt(2 * failure.foot_stiffness / failure.robot_mass);
}

std::string solver_advice(const SolverFailure& failure) {
  using contact::ContactSolverType;
  const contact::SolverResult& r = failure.result;
  std::vector<std::string> tips;
  if (failure.solver == ContactSolverType::admm)
    tips.push_back("Contact/Solver = auto (Gauss-Seidel, then semismooth Newton when it stalls; "
                   "ADMM is not robust on the rank-deficient problems of many contact points, "
                   "docs/contact_solvers.md)");
  else if (failure.solver == ContactSolverType::gauss_seidel)
    tips.push_back("Contact/Solver = auto (semismooth Newton takes over when Gauss-Seidel "
                   "stalls)");
  const double ratio = stiffness_step_ratio(failure);
  if (r.status == contact::SolverStatus::non_finite) {
    std::ostringstream tip;
    tip << "Simulation/Time step = " << one_digit(failure.time_step / 4, false)
        << " (the solve produced non-finite values)";
    tips.push_back(tip.str());
  } else if (ratio > 1) {
    std::ostringstream tip;
    tip << "Simulation/Time step = " << one_digit(failure.time_step / ratio, false)
        << " (the feet, " << failure.foot_stiffness << " N/m each under " << failure.robot_mass
        << " kg, give dt sqrt(2 k / m) = " << ratio
        << " at this step: the contact problem is nearly rigid and badly conditioned; "
           "the suggested step makes it 1)";
    tips.push_back(tip.str());
  }
  if (r.status == contact::SolverStatus::max_iterations) {
    std::ostringstream tip;
    tip << "Contact/Max iterations = " << 4 * failure.max_iterations
        << " (the solver used its budget of " << failure.max_iterations;
    if (r.finished_by == ContactSolverType::newton)
      tip << "; Newton may need thousands of iterations on redundant contacts";
    tip << ")";
    tips.push_back(tip.str());
  }
  if (r.residual <= 100 * failure.tolerance) {
    std::ostringstream tip;
    tip << "Contact/Tolerance = " << one_digit(r.residual, true) << " (the solve stalled at "
        << r.residual << " m/s, within 100 x the tolerance " << failure.tolerance << " m/s)";
    tips.push_back(tip.str());
  }
  std::ostringstream out;
  out << "try: ";
  for (std::size_t i = 0; i < tips.size(); ++i)
    out << (i ? "; or " : "") << tips[i];
  return out.str();
}

} // namespace plantar::app
