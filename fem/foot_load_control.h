#pragma once
// The force-controlled static contact (issue 26): the foot's rigid displacement that carries a
// given load. With w = (t_z, theta_x, theta_y) the foot's vertical translation (m) and tilts
// (rad) (its other components kept), F(w) the force of the foot on the sole and M(w) its moment
// about the rotation point p (fem/distributed_contact.h: the sums of (K u) over the top nodes),
// solve
//   r(w) = (F_z + N, M_x - M_x*, M_y - M_y*) = 0     (N > 0 presses the sole down)
// by a quasi-Newton (Broyden) iteration: the Jacobian by forward differences at the start, then
// rank-one updates; each step halved (up to 10 times) until |r| decreases. Converged when
//   |F_z + N| <= tolerance N  and  |M - M*| <= tolerance N L,
// L the largest distance from p to a contact node (m). Each evaluation is a full contact solve.

#include "fem/distributed_contact.h"

namespace plantar::fem {

struct FootLoad {
  double normal_force = 600; ///< N, > 0: the foot pushes the sole down with this force
  double moment_x = 0;       ///< N m, of the foot on the sole about the rotation point
  double moment_y = 0;       ///< N m
};

struct FootLoadSettings {
  double tolerance = 1e-8;          ///< relative, (0, 1e-2]
  unsigned int max_iterations = 40; ///< quasi-Newton steps, [1, 1000]
};

struct FootLoadReport {
  unsigned int iterations = 0;     ///< quasi-Newton steps
  unsigned int contact_solves = 0; ///< contact solves (evaluations of r)
  double force_error = 0;          ///< |F_z + N| / N at the end
  double moment_error = 0;         ///< |M - M*| / (N L) at the end
};

/// Finds w (see above) starting from @p foot's values, which it overwrites; @p problem holds
/// the last solve (the answer) on return. Collective.
/// @throws std::invalid_argument if N <= 0 or a setting is out of range;
/// @throws std::runtime_error naming the iteration and the errors if it does not converge, or
///   if the sole cannot be brought into contact.
FootLoadReport solve_for_foot_load(DistributedContact& problem, const FootLoad& load,
                                   const FootLoadSettings& settings, RigidMotion& foot);

} // namespace plantar::fem
