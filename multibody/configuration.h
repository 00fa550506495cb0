#pragma once
// Operations on the configuration manifold (R^3 x S^3 for the free base, R for 1-DoF joints).

#include "multibody/model.h"

#include <Eigen/Core>

namespace plantar::multibody {

/// q_out = q (+) dt v: for the free base, oMb+ = oMb exp6(dt v_base) (v_base in the base
/// frame, see spatial.h) and the quaternion is renormalised; 1-DoF joints: q + dt v.
/// @param q size nq, @param v size nv, @param dt s, @param q_out size nq (may alias q).
/// Allocates nothing.
void integrate(const Model& model, const Eigen::Ref<const Eigen::VectorXd>& q,
               const Eigen::Ref<const Eigen::VectorXd>& v, double dt,
               Eigen::Ref<Eigen::VectorXd> q_out);

/// Normalises the base quaternion of q in place (no-op for fixed-base models).
void normalize_configuration(const Model& model, Eigen::Ref<Eigen::VectorXd> q);

} // namespace plantar::multibody
