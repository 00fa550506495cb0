#pragma once
// Helpers shared by the fem tests: small meshes and exact fields.

#include "fem/discretization.h"
#include "fem/linear_elasticity.h"

#include <deal.II/grid/grid_generator.h>
#include <deal.II/grid/tria.h>

#include <cmath>
#include <filesystem>
#include <string>

namespace plantar::fem::testing {

/// Box [0, a] x [0, b] x [0, c] with n_x x n_y x n_z hexahedra, or each cube
/// split into tetrahedra. Boundary ids: 0/1 at x = 0/a, 2/3 at y, 4/5 at z.
inline void make_box(dealii::Triangulation<3>& tria, CellKind kind, unsigned int n_x,
                     unsigned int n_y, unsigned int n_z, double a, double b, double c) {
  const dealii::Point<3> lower(0, 0, 0), upper(a, b, c);
  if (kind == CellKind::hexahedron)
    dealii::GridGenerator::subdivided_hyper_rectangle(tria, {n_x, n_y, n_z}, lower, upper);
  else
    dealii::GridGenerator::subdivided_hyper_rectangle_with_simplices(tria, {n_x, n_y, n_z}, lower,
                                                                     upper);
  // Colorize by hand (deal.II 9.4 cannot colorize the simplex variant).
  const double size[3] = {a, b, c};
  for (const auto& cell : tria.active_cell_iterators())
    for (const auto& face : cell->face_iterators())
      if (face->at_boundary()) {
        const auto center = face->center();
        for (unsigned int d = 0; d < 3; ++d) {
          if (std::abs(center[d]) < 1e-9 * size[d])
            face->set_boundary_id(2 * d);
          else if (std::abs(center[d] - size[d]) < 1e-9 * size[d])
            face->set_boundary_id(2 * d + 1);
        }
      }
}

inline std::filesystem::path source_path(const std::string& relative) {
  return std::filesystem::path(PLANTAR_SOURCE_DIR) / relative;
}

inline std::filesystem::path test_cache_dir() {
  return std::filesystem::current_path() / "mesh-cache";
}

} // namespace plantar::fem::testing
