#pragma once
// The finite element of a sole: vector-valued Lagrange elements of degree 1
// or 2 on tetrahedra (P1, P2) or hexahedra (Q1, Q2), with the matching
// mapping and Gauss quadratures (degree + 1 points per direction).

#include "fem/mesh_import.h"

#include <deal.II/base/quadrature.h>
#include <deal.II/fe/fe_system.h>
#include <deal.II/fe/mapping.h>

#include <memory>
#include <string>

namespace plantar::fem {

struct Discretization {
  /// @param kind cell kind of the mesh; @param degree 1 or 2 (throws otherwise).
  Discretization(CellKind kind, unsigned int degree);

  CellKind kind;
  unsigned int degree;
  std::unique_ptr<dealii::FESystem<3>> fe;     ///< 3 components (u_x, u_y, u_z), m
  std::unique_ptr<dealii::Mapping<3>> mapping; ///< affine/trilinear geometry
  dealii::Quadrature<3> cell_quadrature;
  dealii::Quadrature<2> face_quadrature;

  std::string name() const; ///< "P1", "P2", "Q1" or "Q2"
};

} // namespace plantar::fem
