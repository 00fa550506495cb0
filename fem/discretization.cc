#include "fem/discretization.h"

#include <deal.II/base/quadrature_lib.h>
#include <deal.II/fe/fe_q.h>
#include <deal.II/fe/fe_simplex_p.h>
#include <deal.II/fe/mapping_fe.h>
#include <deal.II/fe/mapping_q.h>

#include <stdexcept>

namespace plantar::fem {

Discretization::Discretization(CellKind kind_, unsigned int degree_)
    : kind(kind_), degree(degree_) {
  if (degree < 1 || degree > 2)
    throw std::invalid_argument("element degree = " + std::to_string(degree) +
                                " is out of range: allowed 1 or 2");
  if (kind == CellKind::tetrahedron) {
    fe = std::make_unique<dealii::FESystem<3>>(dealii::FE_SimplexP<3>(degree), 3);
    mapping = std::make_unique<dealii::MappingFE<3>>(dealii::FE_SimplexP<3>(1));
    cell_quadrature = dealii::QGaussSimplex<3>(degree + 1);
    face_quadrature = dealii::QGaussSimplex<2>(degree + 1);
  } else {
    fe = std::make_unique<dealii::FESystem<3>>(dealii::FE_Q<3>(degree), 3);
    mapping = std::make_unique<dealii::MappingQ<3>>(1);
    cell_quadrature = dealii::QGauss<3>(degree + 1);
    face_quadrature = dealii::QGauss<2>(degree + 1);
  }
}

std::string Discretization::name() const {
  return (kind == CellKind::tetrahedron ? "P" : "Q") + std::to_string(degree);
}

} // namespace plantar::fem
