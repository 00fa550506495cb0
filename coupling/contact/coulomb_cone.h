#pragma once
// The exact (round, not faceted) Coulomb cone of one contact, in the contact
// frame (n, t1, t2):  K_mu = { p : ||(p_t1, p_t2)|| <= mu p_n }, and its dual
// K_mu^* = { v : mu ||(v_t1, v_t2)|| <= v_n }.

#include <Eigen/Core>

namespace plantar::coupling {

/// Euclidean projection of @p x = (n, t1, t2) onto K_mu (closed form):
///   ||x_t|| <= mu x_n          -> x
///   mu ||x_t|| <= -x_n         -> 0
///   otherwise                  -> s (1, mu x_t/||x_t||), s = (x_n + mu ||x_t||)/(1 + mu^2).
/// @pre mu >= 0 (mu = 0 is the ray p_t = 0, p_n >= 0).
Eigen::Vector3d project_onto_cone(const Eigen::Vector3d& x, double mu);

/// Euclidean projection onto the dual cone K_mu^* (mu = 0: half-space v_n >= 0).
Eigen::Vector3d project_onto_dual_cone(const Eigen::Vector3d& x, double mu);

/// De Saxce's modified velocity for a contact: v + (b + mu ||v_t||) e_n. The
/// contact law is p in K_mu, this vector in K_mu^*, and their dot product zero.
Eigen::Vector3d de_saxce_velocity(const Eigen::Vector3d& velocity, double normal_bias, double mu);

/// Natural-map residual of one contact, in velocity units (m/s):
///   || p - P_K(p - eta vt) || / eta,   vt = de_saxce_velocity(v, b, mu),
/// with eta > 0 (N s per m/s, e.g. 3 / trace(W_kk)). Zero iff the contact law holds.
double contact_residual(const Eigen::Vector3d& impulse, const Eigen::Vector3d& velocity,
                        double normal_bias, double mu, double eta);

} // namespace plantar::coupling
