#include "coupling/contact/coulomb_cone.h"

#include <cmath>

namespace plantar::coupling {

namespace {
// sqrt(a^2 + b^2) without std::hypot's overflow guard (several times slower; impulses and
// velocities here are far from 1e154).
inline double norm2(double a, double b) {
  return std::sqrt(a * a + b * b);
}
} // namespace

Eigen::Vector3d project_onto_cone(const Eigen::Vector3d& x, double mu) {
  const double normal = x[0];
  const double tangent_norm = norm2(x[1], x[2]);
  if (tangent_norm <= mu * normal)
    return x;
  if (mu * tangent_norm <= -normal)
    return Eigen::Vector3d::Zero();
  const double scale = (normal + mu * tangent_norm) / (1.0 + mu * mu);
  Eigen::Vector3d out;
  out[0] = scale;
  // tangent_norm > 0 here: tangent_norm = 0 with normal < 0 is caught above.
  out[1] = mu * scale * x[1] / tangent_norm;
  out[2] = mu * scale * x[2] / tangent_norm;
  return out;
}

Eigen::Vector3d project_onto_dual_cone(const Eigen::Vector3d& x, double mu) {
  // Moreau: x = P_K*(x) + P_{-K}(x), with -K the polar of K*.
  return x + project_onto_cone(-x, mu);
}

Eigen::Vector3d de_saxce_velocity(const Eigen::Vector3d& velocity, double normal_bias, double mu) {
  Eigen::Vector3d out = velocity;
  out[0] += normal_bias + mu * norm2(velocity[1], velocity[2]);
  return out;
}

double contact_residual(const Eigen::Vector3d& impulse, const Eigen::Vector3d& velocity,
                        double normal_bias, double mu, double eta) {
  const Eigen::Vector3d modified = de_saxce_velocity(velocity, normal_bias, mu);
  return (impulse - project_onto_cone(impulse - eta * modified, mu)).norm() / eta;
}

} // namespace plantar::coupling
