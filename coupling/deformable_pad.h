#pragma once
// A deformable pad (issue 22): a linear-elastic FEM body with its own gmsh .geo and
// materials, fixed by its "top" face on a named link of a robot and touching the ground by
// its "bottom" face (the FEM "sole" generalised: heel pads, knee pads, hand pads, several per
// robot). It is condensed once onto its contact nodes (coupling/condensed_sole.h) and handed
// to the stepper in the LINK frame.
//
// Frames. The mesh is written in the pad frame (meshes/pad_knee.geo, meshes/sole_box.geo:
// origin at the centre of the top face, pad in z <= 0, contact face below). The pad frame is
// placed on the link by a translation t (m, link frame) and a rotation R = Rz(yaw) Ry(pitch)
// Rx(roll) (URDF's rpy convention, rad): x_link = t + R x_pad. Then, for contact nodes k, l,
//   p_k,link = t + R p_k,pad,        C_link(k, l) = R C_pad(k, l) R^T   (m/N),
// (coupling::rotate_compliance_to_contact_frames with identity contact frames).
//
// Vertical stiffness. k_z = 1^T C_zz^-1 1 (N/m), with C_zz the n x n block of the pad-frame
// compliance on the z components of the contact nodes: the total normal force needed to push
// every contact node by the same displacement along pad z while the tangential (x, y) forces on
// the nodes are zero, per unit of that displacement (a rigid, flat, frictionless punch pressing
// the pad; it is the spring constant of a body resting level on the pad on frictionless ground).

#include "coupling/condensed_sole.h"
#include "fem/mesh_import.h"

#include <deal.II/grid/tria.h>

#include <Eigen/Core>

#include <filesystem>
#include <map>
#include <string>

namespace plantar::coupling {

struct PadDescription {
  std::string name; ///< non-empty, used in messages (e.g. "left_knee")
  /// gmsh .geo source with physical surfaces "top" (attached to the link) and "bottom"
  /// (contact) and one physical volume per material region. A relative path is resolved by
  /// fem::resolve_path against the working directory, then the Plantar source tree.
  std::filesystem::path geometry_file = "meshes/pad_knee.geo";
  /// gmsh -setnumber NAME VALUE overrides (e.g. {"PadThickness", 0.01}, {"PadHex", 1}); finite.
  std::map<std::string, double> mesh_numbers;
  std::filesystem::path cache_directory; ///< generated meshes; empty: fem::default_mesh_cache()
  std::string gmsh_executable = "gmsh";  ///< non-empty
  /// Materials by physical volume, fem::parse_material_specs syntax, linear law only, e.g.
  /// "pad: E=1e6, nu=0.3" or "shell: E=4e6, nu=0.3; core: E=1e6, nu=0.45".
  std::string materials = "pad: E=1e6, nu=0.3";
  unsigned int degree = 1;                               ///< Lagrange degree, 1 or 2
  std::string link;                                      ///< the link carrying the pad, non-empty
  Eigen::Vector3d translation = Eigen::Vector3d::Zero(); ///< pad origin in the link frame, m
  Eigen::Vector3d rpy = Eigen::Vector3d::Zero(); ///< roll, pitch, yaw (rad, finite): pad -> link
  double friction = 1.0;                         ///< Coulomb mu against the ground, [0, 100]

  /// Throws std::invalid_argument naming the pad, the field, its value and the allowed range.
  void validate() const;
  /// R = Rz(yaw) Ry(pitch) Rx(roll), pad frame -> link frame.
  Eigen::Matrix3d rotation() const;
};

/// Generates (or reuses from the cache) and imports @p description's mesh into @p tria (pad
/// frame, m) and returns its physical groups, which have "top" and "bottom". Sets @p thickness
/// to the mesh's extent along pad z (m). @throws std::runtime_error if gmsh fails or a surface
/// is missing.
fem::PhysicalGroups mesh_pad(const PadDescription& description, dealii::Triangulation<3>& tria,
                             double& thickness);

class DeformablePad {
public:
  /// Validates @p description, generates (or reuses from the cache) the mesh, imports it,
  /// resolves the materials against its volumes and condenses it onto the "bottom" nodes.
  /// @throws std::invalid_argument on a bad description, material string or material region;
  /// @throws std::runtime_error if gmsh fails, the mesh lacks "top" or "bottom", or the
  ///   condensation fails (coupling/condensed_sole.h).
  explicit DeformablePad(const PadDescription& description);

  const PadDescription& description() const { return description_; }
  const std::string& name() const { return description_.name; }
  const std::string& link() const { return description_.link; }
  double friction() const { return description_.friction; }
  /// R, pad frame -> link frame.
  const Eigen::Matrix3d& rotation() const { return rotation_; }

  int n_contacts() const { return condensed_.n_contacts(); }
  /// Contact node positions in the link frame, (3 x n), m; column k is node k.
  const Eigen::Matrix3Xd& contact_positions() const { return link_positions_; }
  /// Compliance in the link frame, (3n x 3n), m/N, node-major (rows 3k..3k+2 = link x, y, z of
  /// node k): blockwise R C R^T; symmetric positive definite.
  const Eigen::MatrixXd& compliance() const { return link_compliance_; }
  /// Extent of the mesh along pad z (m): the distance from the top to the contact face of a
  /// flat pad.
  double thickness() const { return thickness_; }
  /// k_z = 1^T C_zz^-1 1 (N/m), pad frame (see above): uniform normal push, no tangential force.
  double vertical_stiffness() const { return vertical_stiffness_; }
  /// The condensed FEM body (pad frame), e.g. for field output: write_vtu(u_c, path) takes
  /// pad-frame node displacements (rotate link-frame ones by R^T).
  const CondensedSole& condensed() const { return condensed_; }

private:
  PadDescription description_;
  Eigen::Matrix3d rotation_;
  double thickness_ = 0; // before condensed_: set while condensed_ is built
  CondensedSole condensed_;
  Eigen::Matrix3Xd link_positions_;
  Eigen::MatrixXd link_compliance_;
  double vertical_stiffness_ = 0;
};

} // namespace plantar::coupling
