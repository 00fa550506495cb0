// Geometry of a 6-DoF leg with HRP-2's structure, read from a multibody::Model, for the
// analytic IK (leg_ik.h).
#pragma once

#include "multibody/model.h"
#include "multibody/walking/humanoid.h"

#include <Eigen/Core>
#include <array>
#include <optional>
#include <string>

namespace plantar::walking {

/// Leg chain: hip yaw (z), hip roll (x), hip pitch (y) meeting at the hip point; knee pitch (y)
/// at (0, thigh_lateral_offset, -thigh_length) from the hip point in the thigh frame; ankle pitch
/// (y) and roll (x) meeting at the ankle point, shank_length below the knee; the sole frame at
/// ankle_to_sole in the ankle-roll body frame (no rotation). All frames parallel to the base at
/// q = 0.
struct LegGeometry {
  LegSide side = LegSide::right;
  Eigen::Vector3d hip_offset = Eigen::Vector3d::Zero(); ///< hip point in the base frame [m]
  double thigh_lateral_offset = 0.0; ///< d, knee offset along the pitch axis [m] (signed, y)
  double thigh_length = 0.0;         ///< L1, hip-pitch axis to knee axis along -z [m], > 0
  double shank_length = 0.0;         ///< L2, knee to ankle along -z [m], > 0
  Eigen::Vector3d ankle_to_sole = Eigen::Vector3d::Zero(); ///< sole origin in the ankle frame [m]
  std::array<std::string, 6> joint_names;  ///< hip yaw, hip roll, hip pitch, knee, ankle p, ankle r
  Eigen::Matrix<double, 6, 1> lower_limit; ///< [rad]
  Eigen::Matrix<double, 6, 1> upper_limit; ///< [rad]
  Eigen::Matrix<double, 6, 1> velocity_limit; ///< [rad/s]
};

/// Reads the geometry of leg @p side of @p humanoid (resolved on @p model, a model without
/// compliant ankles) if the chain has the structure above: revolute axes (z, x, y, y, y, x),
/// no rotated joint frames, hip axes and ankle axes intersecting, knee offset in the thigh's
/// y-z plane, shank along -z, the sole frame on the ankle-roll body without rotation.
/// Returns std::nullopt otherwise, with the first mismatch (joint and value) in @p reason.
std::optional<LegGeometry> analytic_leg_geometry(const multibody::Model& model,
                                                 const Humanoid& humanoid, LegSide side,
                                                 std::string& reason);

/// Same, but throws std::runtime_error with the reason if the structure does not fit.
LegGeometry read_leg_geometry(const multibody::Model& model, const Humanoid& humanoid,
                              LegSide side);

} // namespace plantar::walking
