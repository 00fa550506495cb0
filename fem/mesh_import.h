#pragma once
// Import of a gmsh MSH 2.2 mesh into deal.II, keeping gmsh's physical groups:
// physical volumes become cell material ids, physical surfaces boundary ids
// (GridIn::read_msh keeps the physical tag), and their names are read from the
// file's $PhysicalNames section.

#include <deal.II/grid/tria.h>

#include <filesystem>
#include <map>
#include <string>
#include <vector>

namespace plantar::fem {

enum class CellKind { tetrahedron, hexahedron };

/// Physical group names of an imported mesh, mapped to deal.II ids.
struct PhysicalGroups {
  std::map<std::string, dealii::types::boundary_id> surfaces; ///< name -> boundary id
  std::map<std::string, dealii::types::material_id> volumes;  ///< name -> material id
  std::map<dealii::types::boundary_id, unsigned int> n_faces; ///< faces per boundary id
  std::map<dealii::types::material_id, unsigned int> n_cells; ///< cells per material id

  /// Boundary id of the surface @p name; throws std::runtime_error naming the
  /// file and the group if the mesh has no such surface or it holds no face.
  dealii::types::boundary_id surface(const std::string& name) const;
  /// Material id of the volume @p name; throws likewise.
  dealii::types::material_id volume(const std::string& name) const;

  std::filesystem::path file; ///< the file the groups came from (for messages)
};

/// Reads @p msh_file (MSH 2.2, 3D, only tetrahedra or only hexahedra) into
/// @p triangulation (cleared first). Checks that every name in
/// @p required_surfaces is a physical surface holding at least one boundary
/// face and that the mesh has cells. Throws std::runtime_error naming the
/// file and the group otherwise.
PhysicalGroups import_mesh(const std::filesystem::path& msh_file,
                           const std::vector<std::string>& required_surfaces,
                           dealii::Triangulation<3>& triangulation);

/// The single cell kind of @p triangulation; throws on mixed meshes.
CellKind cell_kind(const dealii::Triangulation<3>& triangulation);

} // namespace plantar::fem
