#include "fem/mesh_import.h"

#include "fem/exception_text.h"

#include <deal.II/grid/grid_in.h>

#include <fstream>
#include <sstream>
#include <stdexcept>

namespace plantar::fem {
namespace {

// Parses "$PhysicalNames / n / dim tag \"name\" ... / $EndPhysicalNames".
void read_physical_names(const std::filesystem::path& file, PhysicalGroups& groups) {
  std::ifstream in(file);
  std::string line;
  while (std::getline(in, line))
    if (line.rfind("$PhysicalNames", 0) == 0) {
      int n_names = 0;
      in >> n_names;
      for (int i = 0; i < n_names; ++i) {
        int dim = 0;
        unsigned int tag = 0;
        std::string name;
        in >> dim >> tag;
        std::getline(in, name);
        const auto first = name.find('"'), last = name.rfind('"');
        if (first == std::string::npos || last <= first)
          throw std::runtime_error("mesh '" + file.string() + "': malformed $PhysicalNames entry");
        name = name.substr(first + 1, last - first - 1);
        if (dim == 2)
          groups.surfaces[name] = static_cast<dealii::types::boundary_id>(tag);
        else if (dim == 3)
          groups.volumes[name] = static_cast<dealii::types::material_id>(tag);
      }
      return;
    }
}

} // namespace

dealii::types::boundary_id PhysicalGroups::surface(const std::string& name) const {
  const auto it = surfaces.find(name);
  if (it == surfaces.end())
    throw std::runtime_error("mesh '" + file.string() + "': no physical surface named '" + name +
                             "'");
  if (n_faces.count(it->second) == 0)
    throw std::runtime_error("mesh '" + file.string() + "': physical surface '" + name +
                             "' holds no boundary face");
  return it->second;
}

dealii::types::material_id PhysicalGroups::volume(const std::string& name) const {
  const auto it = volumes.find(name);
  if (it == volumes.end())
    throw std::runtime_error("mesh '" + file.string() + "': no physical volume named '" + name +
                             "'");
  if (n_cells.count(it->second) == 0)
    throw std::runtime_error("mesh '" + file.string() + "': physical volume '" + name +
                             "' holds no cell");
  return it->second;
}

PhysicalGroups import_mesh(const std::filesystem::path& msh_file,
                           const std::vector<std::string>& required_surfaces,
                           dealii::Triangulation<3>& triangulation) {
  std::ifstream in(msh_file);
  if (!in)
    throw std::runtime_error("mesh: cannot read '" + msh_file.string() + "'");
  triangulation.clear();
  dealii::GridIn<3> grid_in(triangulation);
  try {
    grid_in.read_msh(in);
  } catch (const std::exception& e) {
    throw std::runtime_error("mesh '" + msh_file.string() +
                             "' could not be read: " + exception_text(e));
  }
  if (triangulation.n_active_cells() == 0)
    throw std::runtime_error("mesh '" + msh_file.string() + "' holds no 3D cell");

  PhysicalGroups groups;
  groups.file = msh_file;
  read_physical_names(msh_file, groups);
  for (const auto& cell : triangulation.active_cell_iterators()) {
    ++groups.n_cells[cell->material_id()];
    for (const auto& face : cell->face_iterators())
      if (face->at_boundary())
        ++groups.n_faces[face->boundary_id()];
  }
  for (const auto& name : required_surfaces)
    groups.surface(name);
  cell_kind(triangulation);
  return groups;
}

CellKind cell_kind(const dealii::Triangulation<3>& triangulation) {
  if (triangulation.all_reference_cells_are_simplex())
    return CellKind::tetrahedron;
  if (triangulation.all_reference_cells_are_hyper_cube())
    return CellKind::hexahedron;
  throw std::runtime_error("mesh mixes cell kinds; use only tetrahedra or only hexahedra");
}

} // namespace plantar::fem
