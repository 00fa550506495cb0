#pragma once
// Workspace and results of the algorithms for one Model (Pinocchio's Data).
// Allocated once by the constructor; the algorithms then allocate nothing.

#include "multibody/model.h"
#include "multibody/spatial.h"

#include <Eigen/Core>
#include <vector>

namespace plantar::multibody {

struct Data {
  explicit Data(const Model& model);

  // Kinematics, per body i (filled by forward_kinematics and the dynamics algorithms).
  std::vector<SE3> liMi;   ///< body i -> parent body coordinates
  std::vector<SE3> oMi;    ///< body i -> world coordinates
  std::vector<Vector6d> v; ///< spatial velocity of body i in its own frame
  std::vector<Vector6d> a; ///< spatial acceleration of body i in its own frame
  std::vector<Vector6d> f; ///< RNEA: force transmitted by joint i, body i's frame

  // Composite rigid-body inertias (CRBA), in body frames.
  std::vector<Inertia> composite;

  Eigen::MatrixXd mass_matrix; ///< M(q), nv x nv (CRBA fills both triangles)
  Eigen::VectorXd tau;         ///< RNEA output, nv
  Eigen::VectorXd bias;        ///< C(q, v) v + G(q), nv (nonlinear_effects)
  Eigen::VectorXd zero_nv;     ///< zeros, nv (scratch)

  Eigen::Vector3d com = Eigen::Vector3d::Zero();     ///< centre of mass, world, m
  Eigen::Matrix3Xd com_jacobian;                     ///< 3 x nv
  Eigen::Matrix<double, 6, Eigen::Dynamic> jacobian; ///< 6 x nv scratch for Jacobians
};

} // namespace plantar::multibody
