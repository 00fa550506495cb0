#pragma once
// Centre of mass and its Jacobian.

#include "multibody/data.h"
#include "multibody/model.h"

#include <Eigen/Core>

namespace plantar::multibody {

/// Centre of mass c = sum_i m_i oMi c_i / sum_i m_i (world, m), written into data.com.
/// Requires forward_kinematics(q).
const Eigen::Vector3d& center_of_mass(const Model& model, Data& data);

/// Jacobian of the centre of mass (3 x nv): J_c = sum_i m_i J_point(i, c_i) / m, written into
/// data.com_jacobian; also updates data.com. Requires forward_kinematics(q). Allocates nothing.
const Eigen::Matrix3Xd& center_of_mass_jacobian(const Model& model, Data& data);

} // namespace plantar::multibody
