#pragma once
// The exact (round, not faceted) Coulomb cone of one contact, in the contact
// frame (n, t1, t2):  K_mu = { p : ||(p_t1, p_t2)|| <= mu p_n }, and its dual
// K_mu^* = { v : mu ||(v_t1, v_t2)|| <= v_n }.

#include <Eigen/Core>
#include <cmath>

namespace plantar::contact {

namespace detail {
// sqrt(a^2 + b^2) without std::hypot's overflow guard (several times slower; impulses and
// velocities here are far from 1e154).
inline double norm2(double a, double b) {
  return std::sqrt(a * a + b * b);
}
} // namespace detail

/// Euclidean projection of @p x = (n, t1, t2) onto K_mu (closed form):
///   ||x_t|| <= mu x_n          -> x
///   mu ||x_t|| <= -x_n         -> 0
///   otherwise                  -> s (1, mu x_t/||x_t||), s = (x_n + mu ||x_t||)/(1 + mu^2).
/// @pre mu >= 0 (mu = 0 is the ray p_t = 0, p_n >= 0).
/// Inline: called per contact in every sweep and residual.
inline Eigen::Vector3d project_onto_cone(const Eigen::Vector3d& x, double mu) {
  const double normal = x[0];
  const double tangent_norm = detail::norm2(x[1], x[2]);
  if (normal >= 0.0 && tangent_norm <= mu * normal) // normal >= 0: mu = 0, x_t = 0, x_n < 0
    return x;
  if (mu * tangent_norm <= -normal)
    return Eigen::Vector3d::Zero();
  const double scale = (normal + mu * tangent_norm) / (1.0 + mu * mu);
  // tangent_norm > 0 here: tangent_norm = 0 with normal < 0 is caught above.
  return Eigen::Vector3d(scale, mu * scale * x[1] / tangent_norm, mu * scale * x[2] / tangent_norm);
}

/// Euclidean projection onto the dual cone K_mu^* (mu = 0: half-space v_n >= 0).
Eigen::Vector3d project_onto_dual_cone(const Eigen::Vector3d& x, double mu);

/// De Saxce's modified velocity for a contact: v + (b + mu ||v_t||) e_n. The
/// contact law is p in K_mu, this vector in K_mu^*, and their dot product zero.
inline Eigen::Vector3d de_saxce_velocity(const Eigen::Vector3d& velocity, double normal_bias,
                                         double mu) {
  Eigen::Vector3d out = velocity;
  out[0] += normal_bias + mu * detail::norm2(velocity[1], velocity[2]);
  return out;
}

/// Natural-map residual of one contact, in velocity units (m/s):
///   || p - P_K(p - eta vt) || / eta,   vt = de_saxce_velocity(v, b, mu),
/// with eta > 0 (N s per m/s, e.g. 3 / trace(W_kk)). Zero iff the contact law holds.
inline double contact_residual(const Eigen::Vector3d& impulse, const Eigen::Vector3d& velocity,
                               double normal_bias, double mu, double eta) {
  const Eigen::Vector3d modified = de_saxce_velocity(velocity, normal_bias, mu);
  return (impulse - project_onto_cone(impulse - eta * modified, mu)).norm() / eta;
}

} // namespace plantar::contact
