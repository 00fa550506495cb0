#pragma once
// An inertial measurement unit fixed to a frame of the model: what it measures at the state
// (q, v) and acceleration a (generalized, nv) of the robot, noise-free.
//   orientation       R_s = R_b R_f                  (sensor -> world)
//   angular velocity  w_s = R_f^T w_b                (rad/s, sensor axes; w_b in body b's frame)
//   linear accel.     f_s = R_s^T (a_p - g)          (m/s^2, sensor axes: the specific force,
//                                                    so +g up when at rest)
// with (R_b, o_b) the pose of the frame's body b, (R_f, r) the frame in b and a_p the
// classical acceleration of the point o_b + R_b r (jacobian.h, point_drift_acceleration with
// the full acceleration in data.a).

#include "multibody/data.h"
#include "multibody/model.h"

#include <Eigen/Core>

namespace plantar::multibody::sensors {

struct ImuReading {
  Eigen::Matrix3d orientation = Eigen::Matrix3d::Identity();     ///< sensor -> world
  Eigen::Vector3d angular_velocity = Eigen::Vector3d::Zero();    ///< rad/s, sensor axes
  Eigen::Vector3d linear_acceleration = Eigen::Vector3d::Zero(); ///< specific force, m/s^2
};

/// The reading of an IMU at model frame @p frame. Requires forward_kinematics(model, data, q,
/// v, a) (a: the generalized acceleration, nv). Allocates nothing.
ImuReading read_imu(const Model& model, const Data& data, int frame);

} // namespace plantar::multibody::sensors
