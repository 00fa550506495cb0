#pragma once
// The robot's links as surfaces for ParaView: the URDF's <visual> geometry (<collision> when a
// link has no <visual>): boxes, cylinders, spheres and mesh files (STL, OBJ, PLY; <mesh
// scale>), and for every link without geometry a "stick": a cylinder of radius r from its
// body's origin to each child joint origin and to each merged frame (e.g. r_sole).
// Surfaces are built (and mesh files read) once, in body coordinates; each output step only
// moves their points by the body placements. One VTK XML PolyData file (.vtp) per output step,
// world frame, zlib-compressed raw binary (appended data):
//   points: Float32 (m), the body origins first, then each shape's (coincident points merged);
//   cells: one VTK_VERTEX per body at its frame origin (the waist origin for body 1), then the
//   shapes' polygons (triangles, quads, 16-sided cylinder caps), Int32 connectivity;
//   cell data "body" (Int32): the Model body index (1 = the free-floating base).

#include "multibody/data.h"
#include "multibody/model.h"

#include <Eigen/Core>

#include <filesystem>
#include <string>
#include <vector>

namespace plantar::app {

/// A surface fixed to a body: polygons over points in body coordinates.
struct LinkShape {
  enum class Kind { box, cylinder, sphere, mesh, stick };
  Kind kind = Kind::box;
  int body = 0;                  ///< Model body index
  std::string source;            ///< the URDF link; stick: the child joint or frame it reaches
  Eigen::Matrix3Xd points;       ///< body coordinates (m)
  std::vector<int> offsets;      ///< polygon k: connectivity[offsets[k] .. offsets[k + 1])
  std::vector<int> connectivity; ///< point indices (into points)
  int n_polygons() const { return static_cast<int>(offsets.size()) - 1; }
};

/// The shapes of every link of @p model (see the file comment), read from @p urdf_file, the
/// URDF the model was built from; mesh file names are relative to its directory (a
/// "file://" prefix is dropped). @p stick_radius (m) > 0. Throws std::invalid_argument on a
/// bad radius, std::runtime_error naming the URDF file (and the link and mesh file name)
/// when the URDF cannot be parsed or a mesh is a package:// URI, missing, unreadable, empty
/// or of an unsupported extension (.stl, .obj, .ply are read).
std::vector<LinkShape> make_link_shapes(const multibody::Model& model,
                                        const std::filesystem::path& urdf_file,
                                        double stick_radius);

/// Writes the shapes at the placements @p data.oMi (forward kinematics done) to @p path
/// (.vtp, see the file comment; written under a temporary name, then renamed). Allocates
/// (output steps only). Throws std::runtime_error naming @p path if it cannot be written.
void write_links_vtp(const multibody::Model& model, const multibody::Data& data,
                     const std::vector<LinkShape>& shapes, const std::filesystem::path& path);

} // namespace plantar::app
