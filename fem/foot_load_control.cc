#include "fem/foot_load_control.h"

#include <cmath>
#include <sstream>
#include <stdexcept>

namespace plantar::fem {

using namespace dealii;

namespace {

Tensor<1, 3> unknowns(const RigidMotion& foot) {
  return Tensor<1, 3>({foot.translation[2], foot.rotation[0], foot.rotation[1]});
}

void set_unknowns(const Tensor<1, 3>& w, RigidMotion& foot) {
  foot.translation[2] = w[0];
  foot.rotation[0] = w[1];
  foot.rotation[1] = w[2];
}

} // namespace

FootLoadReport solve_for_foot_load(DistributedContact& problem, const FootLoad& load,
                                   const FootLoadSettings& settings, RigidMotion& foot) {
  if (!(load.normal_force > 0) || !std::isfinite(load.normal_force)) {
    std::ostringstream msg;
    msg << "static contact: normal force = " << load.normal_force << " N: must be > 0";
    throw std::invalid_argument(msg.str());
  }
  if (!(settings.tolerance > 0 && settings.tolerance <= 1e-2) || settings.max_iterations < 1 ||
      settings.max_iterations > 1000)
    throw std::invalid_argument("static contact: force control tolerance must be in (0, 1e-2] "
                                "and its maximum iterations in [1, 1000]");
  FootLoadReport report;
  double length = 0;
  for (const auto& node : problem.gather_contact_nodes())
    length = std::max(length, (node.position - foot.center).norm());
  const double n = load.normal_force;
  // Scaled residual: force error / N, moment errors / (N L).
  const auto residual = [&](const Tensor<1, 3>& w) {
    set_unknowns(w, foot);
    problem.solve(foot);
    ++report.contact_solves;
    const Tensor<1, 3> force = problem.foot_force(), moment = problem.foot_moment(foot.center);
    return Tensor<1, 3>({(force[2] + n) / n, (moment[0] - load.moment_x) / (n * length),
                         (moment[1] - load.moment_y) / (n * length)});
  };
  const auto converged = [&](const Tensor<1, 3>& r) {
    report.force_error = std::abs(r[0]);
    report.moment_error = std::hypot(r[1], r[2]);
    return report.force_error <= settings.tolerance && report.moment_error <= settings.tolerance;
  };
  Tensor<1, 3> w = unknowns(foot), r = residual(w);
  // Bring the sole into contact: lower the foot until it carries a force.
  for (int k = 0; r[0] >= 1.0 - 1e-12; ++k) {
    if (k == 30)
      throw std::runtime_error("static contact: the foot carries no force after lowering it by " +
                               std::to_string(-w[0]) + " m");
    w[0] -= 1e-3 * length * (1 << std::min(k, 10));
    r = residual(w);
  }
  if (converged(r))
    return report; // problem holds the solve at w
  // The Jacobian dr/dw by forward differences (the loop below solves at w + step last).
  const double steps[3] = {1e-6 * length, 1e-6, 1e-6};
  Tensor<2, 3> jacobian;
  for (unsigned int j = 0; j < 3; ++j) {
    Tensor<1, 3> shifted = w;
    shifted[j] += steps[j];
    const Tensor<1, 3> r_shifted = residual(shifted);
    for (unsigned int i = 0; i < 3; ++i)
      jacobian[i][j] = (r_shifted[i] - r[i]) / steps[j];
  }
  while (!converged(r)) {
    if (report.iterations == settings.max_iterations) {
      std::ostringstream msg;
      msg << "static contact: force control did not converge after " << report.iterations
          << " iterations: force error " << report.force_error << ", moment error "
          << report.moment_error << " > tolerance " << settings.tolerance;
      throw std::runtime_error(msg.str());
    }
    ++report.iterations;
    if (std::abs(determinant(jacobian)) < 1e-300)
      throw std::runtime_error("static contact: force control: singular Jacobian at iteration " +
                               std::to_string(report.iterations));
    Tensor<1, 3> step = -(invert(jacobian) * r), r_new;
    for (int halving = 0;; ++halving) {
      r_new = residual(w + step);
      if (r_new.norm() < r.norm() || halving == 10)
        break;
      step *= 0.5;
    }
    // Broyden: J += (dr - J dw) dw^T / (dw . dw).
    const Tensor<1, 3> correction = (r_new - r - jacobian * step) / (step * step);
    jacobian += outer_product(correction, step);
    w += step;
    r = r_new;
  }
  set_unknowns(w, foot);
  return report;
}

} // namespace plantar::fem
