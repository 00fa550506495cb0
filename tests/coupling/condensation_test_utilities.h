#pragma once
// Helpers shared by the condensation tests: small sole-like boxes, the sole
// mesh from meshes/sole_box.geo, and dense references.

#include "coupling/condensed_sole.h"
#include "fem/mesh_generator.h"
#include "fem/mesh_import.h"

#include <deal.II/grid/grid_generator.h>
#include <deal.II/grid/tria.h>

#include <Eigen/Core>

#include <cmath>
#include <filesystem>
#include <map>
#include <string>

namespace plantar::coupling::testing {

/// Box [-a/2, a/2] x [-b/2, b/2] x [-c, 0] (a sole: top face at z = 0) with
/// n_x x n_y x n_z hexahedra or each split into tetrahedra.
/// Boundary ids: 0 = top (z = 0), 1 = bottom (z = -c), 2 = sides.
inline void make_sole_box(dealii::Triangulation<3>& tria, fem::CellKind kind, unsigned int n_x,
                          unsigned int n_y, unsigned int n_z, double a, double b, double c) {
  const dealii::Point<3> lower(-a / 2, -b / 2, -c), upper(a / 2, b / 2, 0);
  if (kind == fem::CellKind::hexahedron)
    dealii::GridGenerator::subdivided_hyper_rectangle(tria, {n_x, n_y, n_z}, lower, upper);
  else
    dealii::GridGenerator::subdivided_hyper_rectangle_with_simplices(tria, {n_x, n_y, n_z}, lower,
                                                                     upper);
  for (const auto& cell : tria.active_cell_iterators())
    for (const auto& face : cell->face_iterators())
      if (face->at_boundary()) {
        const double z = face->center()[2];
        face->set_boundary_id(std::abs(z) < 1e-9 * c ? 0 : std::abs(z + c) < 1e-9 * c ? 1 : 2);
      }
}

/// The sole of meshes/sole_box.geo (gmsh, cached in ./mesh-cache), imported
/// into @p tria; returns its physical groups ("top", "bottom").
inline fem::PhysicalGroups load_sole_mesh(dealii::Triangulation<3>& tria,
                                          const std::map<std::string, double>& numbers) {
  fem::MeshRequest request;
  request.geo_file = std::filesystem::path(PLANTAR_SOURCE_DIR) / "meshes" / "sole_box.geo";
  request.numbers = numbers;
  request.cache_directory = std::filesystem::current_path() / "mesh-cache";
  const auto msh = fem::generate_mesh(request);
  return fem::import_mesh(msh, {"top", "bottom"}, tria);
}

/// Dense K restricted to the unconstrained dofs of @p sole, in global dof
/// order; @p free_dofs receives their global indices.
inline Eigen::MatrixXd dense_free_stiffness(const CondensedSole& sole,
                                            std::vector<unsigned int>& free_dofs) {
  const auto& elasticity = sole.elasticity();
  const auto& k = elasticity.stiffness_matrix();
  std::vector<int> index(k.m(), -1);
  free_dofs.clear();
  for (unsigned int dof = 0; dof < k.m(); ++dof)
    if (!elasticity.constraints().is_constrained(dof)) {
      index[dof] = static_cast<int>(free_dofs.size());
      free_dofs.push_back(dof);
    }
  Eigen::MatrixXd dense = Eigen::MatrixXd::Zero(free_dofs.size(), free_dofs.size());
  for (unsigned int row = 0; row < k.m(); ++row)
    if (index[row] >= 0)
      for (auto entry = k.begin(row); entry != k.end(row); ++entry)
        if (index[entry->column()] >= 0)
          dense(index[row], index[entry->column()]) = entry->value();
  return dense;
}

inline double max_abs(const Eigen::Ref<const Eigen::MatrixXd>& m) {
  return m.cwiseAbs().maxCoeff();
}

} // namespace plantar::coupling::testing
