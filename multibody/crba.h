#pragma once
// Composite rigid-body algorithm for the joint-space inertia matrix (Featherstone 2008, table 6.2).

#include "multibody/data.h"
#include "multibody/model.h"

#include <Eigen/Core>

namespace plantar::multibody {

/// Joint-space inertia M(q) (nv x nv, kg / kg m / kg m^2), both triangles, written into
/// data.mass_matrix: M_ij = S_j^T X_j<-i^* (I^c_i S_i) for j ancestor of (or equal to) i,
/// with I^c_i the composite inertia of i's subtree (data.composite). Fills data.liMi and oMi.
/// For a free base the base block uses the base-frame velocity of model.h. Allocates nothing.
const Eigen::MatrixXd& crba(const Model& model, Data& data,
                            const Eigen::Ref<const Eigen::VectorXd>& q);

/// The same without the forward kinematics: uses data.liMi as left by forward_kinematics,
/// rnea or nonlinear_effects at the same q (saves one kinematic pass when both are needed).
const Eigen::MatrixXd& crba_from_placements(const Model& model, Data& data);

} // namespace plantar::multibody
