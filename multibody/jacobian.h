#pragma once
// Body, frame and point Jacobians and their drift terms J-dot v.
// All require forward_kinematics(model, data, q) first (the drift terms:
// forward_kinematics(model, data, q, v, zero) so that data.a holds the drift accelerations).

#include "multibody/data.h"
#include "multibody/model.h"

#include <Eigen/Core>

namespace plantar::multibody {

/// Spatial Jacobian of body b in the world frame at the world origin (6 x nv, Pinocchio's
/// WORLD): [v_O; w] = J v, column k of ancestor joint j = oMj.act_motion(S_j e_k), others 0.
void body_jacobian_world(const Model& model, const Data& data, int body,
                         Eigen::Ref<Eigen::MatrixXd> jacobian);

/// Linear velocity Jacobian (3 x nv, world axes) of a point fixed to body b, given in body
/// coordinates (m): v_p = J v, column = v_O + w x p_world.
void point_jacobian(const Model& model, const Data& data, int body, const Eigen::Vector3d& point,
                    Eigen::Ref<Eigen::MatrixXd> jacobian);

/// Jacobian of body b (6 x nv) with world-aligned axes at the body origin o_b (Pinocchio's
/// LOCAL_WORLD_ALIGNED for the body frame): rows 0-2 the velocity of o_b (m/s per unit v),
/// rows 3-5 the angular velocity; column of ancestor joint j = [R_j s_lin + (R_j s_ang) x
/// (o_b - o_j); R_j s_ang], other columns 0. A point p fixed to b moves with
/// v_p = J_lin v - (p - o_b) x J_ang v. Allocates nothing.
void body_origin_jacobian(const Model& model, const Data& data, int body,
                          Eigen::Ref<Eigen::MatrixXd> jacobian);

/// Frame Jacobian (6 x nv) with world-aligned axes at the frame origin (Pinocchio's
/// LOCAL_WORLD_ALIGNED): rows 0-2 the origin's linear velocity, rows 3-5 the angular velocity.
void frame_jacobian(const Model& model, const Data& data, int frame,
                    Eigen::Ref<Eigen::MatrixXd> jacobian);

/// J-dot v of point_jacobian: the point's classical acceleration (world, m/s^2) at zero joint
/// acceleration, R_b (a_v + a_w x r + w x (v + w x r)) with (v, w), (a_v, a_w) body b's velocity
/// and drift acceleration in its frame and r the point in body coordinates.
Eigen::Vector3d point_drift_acceleration(const Model& model, const Data& data, int body,
                                         const Eigen::Vector3d& point);

/// J-dot v of frame_jacobian: [classical linear acceleration of the origin; angular
/// acceleration], world axes, at zero joint acceleration.
Vector6d frame_drift_acceleration(const Model& model, const Data& data, int frame);

} // namespace plantar::multibody
