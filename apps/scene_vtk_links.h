#pragma once
// The robot's links as simple solids for ParaView: the URDF's <visual> boxes and cylinders
// (<collision> when a link has no <visual>; spheres drawn as cubes of the same diameter,
// meshes ignored), and for every link without such geometry a "stick": a cylinder of radius
// r from its body's origin to each child joint origin and to each merged frame (e.g. r_sole).
// One VTU per output step, in the world frame:
//   boxes: VTK_HEXAHEDRON; cylinders: n_sides VTK_QUAD sides and two VTK_POLYGON caps;
//   one VTK_VERTEX per body at its frame origin (the waist origin for body 1);
//   cell data "body" (Int32): the Model body index (1 = the free-floating base).

#include "multibody/data.h"
#include "multibody/model.h"
#include "multibody/spatial.h"

#include <Eigen/Core>

#include <filesystem>
#include <vector>

namespace urdf {
class ModelInterface;
}

namespace plantar::app {

/// A solid fixed to a body.
struct LinkShape {
  enum class Kind { box, cylinder };
  Kind kind = Kind::box;
  int body = 0;             ///< Model body index
  multibody::SE3 placement; ///< shape -> body coordinates; cylinder axis = shape z
  Eigen::Vector3d size;     ///< box: edge lengths (m); cylinder: (radius, radius, length) m
};

/// The shapes of every link of @p model (see the file comment). @p urdf is the file the model
/// was built from; @p stick_radius (m) > 0. Throws std::invalid_argument on a bad radius.
std::vector<LinkShape> make_link_shapes(const multibody::Model& model,
                                        const urdf::ModelInterface& urdf, double stick_radius);

/// Writes the shapes at the placements @p data.oMi (forward kinematics done) to @p path
/// (ASCII VTU, atomically). Allocates (output steps only).
void write_links_vtu(const multibody::Model& model, const multibody::Data& data,
                     const std::vector<LinkShape>& shapes, const std::filesystem::path& path);

} // namespace plantar::app
