#include "contact/coulomb_cone.h"

namespace plantar::contact {

Eigen::Vector3d project_onto_dual_cone(const Eigen::Vector3d& x, double mu) {
  // Moreau: x = P_K*(x) + P_{-K}(x), with -K the polar of K*.
  return x + project_onto_cone(-x, mu);
}

} // namespace plantar::contact
