#pragma once
// Building a Model from a URDF file (urdfdom): revolute, continuous, prismatic and fixed
// joints, limits, link inertias, every link kept as a named frame; optional compliant ankles.

#include "multibody/model.h"

#include <Eigen/Core>
#include <string>
#include <vector>

namespace plantar::multibody {

/// The passive compliant ankle of HRP-2 as modelled by Nakaoka et al. and David et al. 2008,
/// eq. 13: three joints inserted between the ankle and each named foot link, at the
/// compliance centre, a vertical translation (foot z), a pitch (foot y) and a roll (foot x)
/// axis, each a linear spring-damper: F = -k_z u - c_z u', tau = -k_r theta - c_r theta'.
/// Defaults: public HRP-2 flexibility values (see docs/multibody.md).
struct CompliantAnkleParameters {
  std::vector<std::string> foot_links; ///< URDF links to make compliant; empty: none
  double linear_stiffness = 40000.0;   ///< N/m, > 0
  double linear_damping = 600.0;       ///< N s/m, >= 0
  double angular_stiffness = 600.0;    ///< N m/rad, > 0 (pitch and roll)
  double angular_damping = 60.0;       ///< N m s/rad, >= 0
  /// Compliance centre in the foot link frame, m (the centre of the rubber bushes).
  Eigen::Vector3d center_in_foot = Eigen::Vector3d::Zero();
};

struct ModelOptions {
  bool floating_base = true; ///< free-flyer root (7 q, 6 v) or root link fixed to the world
  Eigen::Vector3d gravity{0.0, 0.0, -9.81}; ///< m/s^2
  CompliantAnkleParameters compliant_ankle;
};

/// Loads @p path. Throws std::runtime_error naming the file and the element for: a missing
/// or unreadable file, a URDF that urdfdom rejects (unknown joint type, missing link, no or
/// several roots: the parser's message is included), a link that is the child of two joints
/// (kinematic loop), floating/planar joints, a negative mass, a body moved by a joint whose
/// subtree has no mass (M would be singular), and std::invalid_argument for bad options.
Model build_model_from_urdf(const std::string& path, const ModelOptions& options = {});

/// Same from a URDF string; @p source_name is used in error messages.
Model build_model_from_urdf_string(const std::string& xml, const ModelOptions& options = {},
                                   const std::string& source_name = "<string>");

} // namespace plantar::multibody
