#pragma once
// Forward kinematics: body placements, spatial velocities and accelerations.

#include "multibody/data.h"
#include "multibody/model.h"

#include <Eigen/Core>

namespace plantar::multibody {

/// Throws std::invalid_argument naming @p what if size != expected.
void check_size(Eigen::Index size, Eigen::Index expected, const char* what);

/// Placement of joint i's motion at configuration q: joint frame (moved) -> joint frame at 0.
/// Free flyer: (R(quaternion), position); revolute: Rot(axis, q); prismatic: Trans(axis q).
SE3 joint_motion(const Model& model, int joint, const Eigen::Ref<const Eigen::VectorXd>& q);

/// Fills data.liMi and data.oMi (oMi = oM_parent liMi, liMi = placement * joint_motion).
/// @param q configuration, size nq.
void forward_kinematics(const Model& model, Data& data, const Eigen::Ref<const Eigen::VectorXd>& q);

/// Also fills the body velocities data.v (body frames): v_i = X_i^-1 v_parent + S_i v_i.
/// @param v velocity, size nv.
void forward_kinematics(const Model& model, Data& data, const Eigen::Ref<const Eigen::VectorXd>& q,
                        const Eigen::Ref<const Eigen::VectorXd>& v);

/// Also fills the body accelerations data.a (body frames, no gravity):
/// a_i = X_i^-1 a_parent + S_i a_i + v_i x (S_i v_i). With a = 0 these are the drift
/// accelerations that give J-dot v (see jacobian.h).
void forward_kinematics(const Model& model, Data& data, const Eigen::Ref<const Eigen::VectorXd>& q,
                        const Eigen::Ref<const Eigen::VectorXd>& v,
                        const Eigen::Ref<const Eigen::VectorXd>& a);

/// World placement of a frame (frame -> world) after forward_kinematics.
SE3 frame_placement(const Model& model, const Data& data, int frame);

} // namespace plantar::multibody
