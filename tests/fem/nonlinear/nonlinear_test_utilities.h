#pragma once
// Helpers of the nonlinear sole tests: Cook's membrane mesh, closed forms.

#include "fem/nonlinear_elasticity.h"

#include <deal.II/grid/grid_generator.h>
#include <deal.II/grid/grid_tools.h>
#include <deal.II/grid/tria.h>

namespace plantar::fem::testing {

/// Cook's membrane (validation.md): corners (0,0), (48,44), (48,60), (0,44)
/// (mm), extruded to thickness @p thickness along z, n x n x 1 hexahedra.
/// Boundary ids: 0 left (x = 0), 1 right (x = 48), 2 bottom edge, 3 top edge, 4/5 z faces.
inline void make_cook_membrane(dealii::Triangulation<3>& tria, unsigned int n, double thickness) {
  dealii::GridGenerator::subdivided_hyper_rectangle(tria, {n, n, 1u}, dealii::Point<3>(0, 0, 0),
                                                    dealii::Point<3>(1, 1, thickness), true);
  dealii::GridTools::transform(
      [](const dealii::Point<3>& p) {
        const double xi = p[0], eta = p[1];
        const double y_bottom = 44 * xi, y_top = 44 + 16 * xi;
        return dealii::Point<3>(48 * xi, y_bottom + eta * (y_top - y_bottom), p[2]);
      },
      tria);
}

} // namespace plantar::fem::testing
