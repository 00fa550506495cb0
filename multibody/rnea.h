#pragma once
// Recursive Newton-Euler inverse dynamics (Featherstone 2008, table 5.1), body frames.

#include "multibody/data.h"
#include "multibody/model.h"

#include <Eigen/Core>

namespace plantar::multibody {

/// Inverse dynamics tau = M(q) a + C(q, v) v + G(q), written into data.tau (size nv, N or N m;
/// for a free base the first 6 entries are the base wrench [force; torque] in the base frame).
/// Gravity enters as the base acceleration a_0 = -g. Also fills data.liMi, oMi, v, a, f.
/// @param q size nq, @param v size nv, @param a size nv. Allocates nothing.
const Eigen::VectorXd& rnea(const Model& model, Data& data,
                            const Eigen::Ref<const Eigen::VectorXd>& q,
                            const Eigen::Ref<const Eigen::VectorXd>& v,
                            const Eigen::Ref<const Eigen::VectorXd>& a);

/// Bias forces b = C(q, v) v + G(q) = rnea(q, v, 0), written into data.bias (size nv).
const Eigen::VectorXd& nonlinear_effects(const Model& model, Data& data,
                                         const Eigen::Ref<const Eigen::VectorXd>& q,
                                         const Eigen::Ref<const Eigen::VectorXd>& v);

/// Gravity torques G(q) = rnea(q, 0, 0), written into data.bias (size nv).
const Eigen::VectorXd& gravity_torques(const Model& model, Data& data,
                                       const Eigen::Ref<const Eigen::VectorXd>& q);

} // namespace plantar::multibody
