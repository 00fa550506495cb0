// Geometry of one 6-DoF HRP-2 leg, read from the URDF, for the analytic IK.
#pragma once

#include <Eigen/Core>
#include <array>
#include <memory>
#include <string>
#include <urdf_model/model.h>

namespace plantar::walking {

enum class LegSide { right, left };

/// Leg chain: hip yaw (z), hip roll (x), hip pitch (y) meeting at the hip point; knee pitch (y)
/// at (0, thigh_lateral_offset, -thigh_length) from the hip point in the thigh frame; ankle pitch
/// (y) and roll (x) meeting at the ankle point, shank_length below the knee; the sole frame at
/// ankle_to_sole in the ankle-roll link frame (no rotation). All frames parallel to BODY at q = 0.
struct LegGeometry {
  LegSide side = LegSide::right;
  Eigen::Vector3d hip_offset = Eigen::Vector3d::Zero(); ///< hip point in the BODY frame [m]
  double thigh_lateral_offset = 0.0; ///< d, knee offset along the pitch axis [m] (signed, y)
  double thigh_length = 0.0;         ///< L1, hip-pitch axis to knee axis along -z [m], > 0
  double shank_length = 0.0;         ///< L2, knee to ankle along -z [m], > 0
  Eigen::Vector3d ankle_to_sole = Eigen::Vector3d::Zero(); ///< sole origin in the ankle frame [m]
  std::array<std::string, 6> joint_names;  ///< hip yaw, hip roll, hip pitch, knee, ankle p, ankle r
  std::string sole_link;                   ///< r_sole or l_sole
  Eigen::Matrix<double, 6, 1> lower_limit; ///< [rad]
  Eigen::Matrix<double, 6, 1> upper_limit; ///< [rad]
  Eigen::Matrix<double, 6, 1> velocity_limit; ///< [rad/s]
};

/// Reads the leg geometry of `side` (joints RLEG_JOINT0..5 / LLEG_JOINT0..5, sole link
/// r_sole / l_sole) from a parsed URDF.
/// @throws std::runtime_error naming the joint and the offending value if the chain does not have
/// the structure above (axes, zero offsets where the closed form needs them, no rotations).
LegGeometry read_leg_geometry(const urdf::ModelInterface& model, LegSide side);

/// Parses `urdf_path` with urdfdom. @throws std::runtime_error naming the file if parsing fails.
std::shared_ptr<urdf::ModelInterface> load_urdf(const std::string& urdf_path);

} // namespace plantar::walking
