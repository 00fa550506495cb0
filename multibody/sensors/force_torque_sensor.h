#pragma once
// A 6-axis force/torque sensor between an ankle and its foot: the wrench the ground applies
// to the foot through its contacts, reported at the sensor frame (the foot's own weight and
// inertia are not in it: the compensated reading of a real sensor).
//   contact wrench about the world origin:  f = sum_k f_k,  n = sum_k x_k x f_k   (world)
//   at the sensor (R_s, o_s):               f_s = R_s^T f,  n_s = R_s^T (n - o_s x f)

#include "multibody/spatial.h"

#include <Eigen/Core>

namespace plantar::multibody::sensors {

/// [f; n] (N, N m, world axes, moment about the world origin) of the contact forces @p forces
/// (3 x n, N, world) at the points @p points (3 x n, m, world).
Vector6d contact_wrench(const Eigen::Ref<const Eigen::Matrix3Xd>& points,
                        const Eigen::Ref<const Eigen::Matrix3Xd>& forces);

/// @p wrench ([f; n] about the world origin, world axes) expressed at the sensor frame
/// @p sensor (sensor -> world): [R^T f; R^T (n - o x f)].
Vector6d wrench_at_sensor(const SE3& sensor, const Vector6d& wrench);

} // namespace plantar::multibody::sensors
