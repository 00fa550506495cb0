#pragma once
// The HRP-2 sole box of the static contact tests and benchmarks, meshed by deal.II (no gmsh):
// [-L/2, L/2] x [-W/2, W/2] x [0, T] (L = 0.2172, W = 0.138, T = 0.02 m), bottom (id 1) on the
// ground z = 0, top id 0, sides 2.

#include <deal.II/grid/grid_generator.h>
#include <deal.II/grid/tria.h>

#include <cmath>

namespace plantar::fem::test {

constexpr double sole_length = 0.2172, sole_width = 0.138, sole_thickness = 0.02;

/// @p n_x x @p n_y x @p n_z hexahedra, refined @p refinements times.
inline void make_sole_box(dealii::Triangulation<3>& tria, unsigned int n_x, unsigned int n_y,
                          unsigned int n_z, unsigned int refinements = 0) {
  dealii::GridGenerator::subdivided_hyper_rectangle(
      tria, {n_x, n_y, n_z}, dealii::Point<3>(-sole_length / 2, -sole_width / 2, 0),
      dealii::Point<3>(sole_length / 2, sole_width / 2, sole_thickness));
  for (const auto& cell : tria.active_cell_iterators())
    for (const auto& face : cell->face_iterators())
      if (face->at_boundary()) {
        const double z = face->center()[2];
        face->set_boundary_id(std::abs(z) < 1e-12                    ? 1
                              : std::abs(z - sole_thickness) < 1e-12 ? 0
                                                                     : 2);
      }
  tria.refine_global(refinements);
}

} // namespace plantar::fem::test
