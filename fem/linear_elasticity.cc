#include "fem/linear_elasticity.h"

#include "fem/contact_condensation.h"

#include <deal.II/base/quadrature_lib.h>
#include <deal.II/dofs/dof_tools.h>
#include <deal.II/fe/fe_values.h>
#include <deal.II/fe/fe_values_extractors.h>
#include <deal.II/lac/dynamic_sparsity_pattern.h>
#include <deal.II/numerics/vector_tools.h>

#include <algorithm>
#include <stdexcept>

namespace plantar::fem {

using namespace dealii;

LinearElasticity::LinearElasticity(const Triangulation<3>& triangulation,
                                   const Discretization& discretization,
                                   const MaterialTable& materials)
    : triangulation_(triangulation), discretization_(discretization), materials_(materials),
      dof_handler_(triangulation) {}

void LinearElasticity::setup(const std::map<types::boundary_id, const Function<3>*>& dirichlet) {
  dof_handler_.distribute_dofs(*discretization_.fe);
  constraints_.clear();
  const Functions::ZeroFunction<3> zero(3);
  for (const auto& [boundary, function] : dirichlet)
    VectorTools::interpolate_boundary_values(*discretization_.mapping, dof_handler_, boundary,
                                             function ? *function : zero, constraints_);
  constraints_.close();

  DynamicSparsityPattern dsp(dof_handler_.n_dofs());
  DoFTools::make_sparsity_pattern(dof_handler_, dsp, constraints_, false);
  sparsity_.copy_from(dsp);
  stiffness_.reinit(sparsity_);
  load_.reinit(dof_handler_.n_dofs());
  external_load_.reinit(dof_handler_.n_dofs());
  solution_.reinit(dof_handler_.n_dofs());
  solver_.reset();
}

void LinearElasticity::assemble(const Function<3>* body_force) {
  stiffness_ = 0;
  load_ = 0;
  external_load_ = 0;
  const auto& fe = *discretization_.fe;
  FEValues<3> fe_values(*discretization_.mapping, fe, discretization_.cell_quadrature,
                        update_values | update_gradients | update_quadrature_points |
                            update_JxW_values);
  const unsigned int n_dofs_cell = fe.n_dofs_per_cell();
  const unsigned int n_q = discretization_.cell_quadrature.size();
  FullMatrix<double> cell_matrix(n_dofs_cell, n_dofs_cell);
  Vector<double> cell_load(n_dofs_cell);
  std::vector<types::global_dof_index> dofs(n_dofs_cell);
  std::vector<SymmetricTensor<2, 3>> eps_phi(n_dofs_cell);
  std::vector<Vector<double>> force_values(n_q, Vector<double>(3));
  const FEValuesExtractors::Vector displacement(0);

  for (const auto& cell : dof_handler_.active_cell_iterators()) {
    fe_values.reinit(cell);
    cell_matrix = 0;
    cell_load = 0;
    const SymmetricTensor<4, 3>& C = materials_[cell->material_id()].stiffness();
    if (body_force)
      body_force->vector_value_list(fe_values.get_quadrature_points(), force_values);
    for (unsigned int q = 0; q < n_q; ++q) {
      for (unsigned int i = 0; i < n_dofs_cell; ++i)
        eps_phi[i] = fe_values[displacement].symmetric_gradient(i, q);
      const double JxW = fe_values.JxW(q);
      for (unsigned int i = 0; i < n_dofs_cell; ++i) {
        const SymmetricTensor<2, 3> C_eps_i = C * eps_phi[i];
        for (unsigned int j = 0; j <= i; ++j)
          cell_matrix(i, j) += (C_eps_i * eps_phi[j]) * JxW;
        if (body_force) {
          const unsigned int component = fe.system_to_component_index(i).first;
          cell_load(i) += fe_values.shape_value(i, q) * force_values[q](component) * JxW;
        }
      }
    }
    for (unsigned int i = 0; i < n_dofs_cell; ++i)
      for (unsigned int j = i + 1; j < n_dofs_cell; ++j)
        cell_matrix(i, j) = cell_matrix(j, i);
    cell->get_dof_indices(dofs);
    constraints_.distribute_local_to_global(cell_matrix, cell_load, dofs, stiffness_, load_);
    for (unsigned int i = 0; i < n_dofs_cell; ++i)
      external_load_(dofs[i]) += cell_load(i);
  }
  solver_.reset();
}

void LinearElasticity::add_traction(types::boundary_id boundary, const Tensor<1, 3>& traction) {
  Functions::ConstantFunction<3> constant(
      std::vector<double>{traction[0], traction[1], traction[2]});
  add_traction(boundary, constant);
}

void LinearElasticity::add_traction(types::boundary_id boundary, const Function<3>& traction) {
  const auto& fe = *discretization_.fe;
  FEFaceValues<3> fe_face(*discretization_.mapping, fe, discretization_.face_quadrature,
                          update_values | update_quadrature_points | update_JxW_values);
  const unsigned int n_dofs_cell = fe.n_dofs_per_cell();
  Vector<double> cell_load(n_dofs_cell);
  std::vector<types::global_dof_index> dofs(n_dofs_cell);
  std::vector<Vector<double>> values(discretization_.face_quadrature.size(), Vector<double>(3));
  for (const auto& cell : dof_handler_.active_cell_iterators())
    for (const unsigned int f : cell->face_indices())
      if (cell->face(f)->at_boundary() && cell->face(f)->boundary_id() == boundary) {
        fe_face.reinit(cell, f);
        traction.vector_value_list(fe_face.get_quadrature_points(), values);
        cell_load = 0;
        for (unsigned int q = 0; q < fe_face.n_quadrature_points; ++q)
          for (unsigned int i = 0; i < n_dofs_cell; ++i) {
            const unsigned int component = fe.system_to_component_index(i).first;
            cell_load(i) += fe_face.shape_value(i, q) * values[q](component) * fe_face.JxW(q);
          }
        cell->get_dof_indices(dofs);
        constraints_.distribute_local_to_global(cell_load, dofs, load_);
        for (unsigned int i = 0; i < n_dofs_cell; ++i)
          external_load_(dofs[i]) += cell_load(i);
      }
}

void LinearElasticity::factorize(const LinearSolverSettings& settings) {
  solver_ = std::make_unique<LinearSolver>(settings);
  solver_->initialize(stiffness_);
}

void LinearElasticity::solve(const LinearSolverSettings& settings) {
  if (!solver_)
    factorize(settings);
  solver_->solve(load_, solution_);
  constraints_.distribute(solution_);
}

void LinearElasticity::solve(const Vector<double>& rhs, Vector<double>& x) const {
  solver().solve(rhs, x);
  constraints_.distribute(x);
}

const LinearSolver& LinearElasticity::solver() const {
  if (!solver_)
    throw std::logic_error("LinearElasticity: factorize() must be called first");
  return *solver_;
}

std::vector<Point<3>> LinearElasticity::support_points() const {
  std::vector<Point<3>> points(dof_handler_.n_dofs());
  DoFTools::map_dofs_to_support_points(*discretization_.mapping, dof_handler_, points);
  return points;
}

std::vector<std::array<types::global_dof_index, 3>>
LinearElasticity::boundary_nodes(types::boundary_id boundary) const {
  return fem::boundary_nodes(dof_handler_, boundary);
}

double LinearElasticity::max_displacement() const {
  double max_norm = 0;
  for (const auto& cell : dof_handler_.active_cell_iterators()) {
    std::vector<types::global_dof_index> dofs(cell->get_fe().n_dofs_per_cell());
    cell->get_dof_indices(dofs);
    const auto& fe = cell->get_fe();
    for (unsigned int i = 0; i < dofs.size(); ++i)
      if (fe.system_to_component_index(i).first == 0) {
        const unsigned int node = fe.system_to_component_index(i).second;
        double norm2 = 0;
        for (unsigned int j = 0; j < dofs.size(); ++j)
          if (fe.system_to_component_index(j).second == node)
            norm2 += solution_(dofs[j]) * solution_(dofs[j]);
        max_norm = std::max(max_norm, std::sqrt(norm2));
      }
  }
  return max_norm;
}

Tensor<1, 3> LinearElasticity::reaction_force(types::boundary_id boundary) const {
  // Internal force f_int = sum_e K_e u_e, assembled without constraints.
  const auto& fe = *discretization_.fe;
  FEValues<3> fe_values(*discretization_.mapping, fe, discretization_.cell_quadrature,
                        update_gradients | update_JxW_values);
  const FEValuesExtractors::Vector displacement(0);
  const unsigned int n_dofs_cell = fe.n_dofs_per_cell();
  std::vector<types::global_dof_index> dofs(n_dofs_cell);
  std::vector<SymmetricTensor<2, 3>> strains(discretization_.cell_quadrature.size());
  Vector<double> internal(dof_handler_.n_dofs());
  for (const auto& cell : dof_handler_.active_cell_iterators()) {
    fe_values.reinit(cell);
    fe_values[displacement].get_function_symmetric_gradients(solution_, strains);
    const auto& material = materials_[cell->material_id()];
    cell->get_dof_indices(dofs);
    for (unsigned int q = 0; q < strains.size(); ++q) {
      const SymmetricTensor<2, 3> stress = material.stress(strains[q]);
      for (unsigned int i = 0; i < n_dofs_cell; ++i)
        internal(dofs[i]) +=
            (stress * fe_values[displacement].symmetric_gradient(i, q)) * fe_values.JxW(q);
    }
  }
  Tensor<1, 3> reaction;
  for (const auto& node : boundary_nodes(boundary))
    for (unsigned int d = 0; d < 3; ++d)
      reaction[d] += internal(node[d]) - external_load_(node[d]);
  return reaction;
}

std::pair<double, double> LinearElasticity::errors(const Function<3>& exact) const {
  // Over-integration; deal.II 9.4's simplex Gauss rules stop at 4 points per direction.
  const Quadrature<3> quadrature =
      discretization_.kind == CellKind::tetrahedron
          ? Quadrature<3>(QGaussSimplex<3>(std::min(discretization_.degree + 2, 4u)))
          : Quadrature<3>(QGauss<3>(discretization_.degree + 3));
  if (quadrature.size() == 0)
    throw std::logic_error("no quadrature rule for the error integration");
  Vector<float> per_cell(triangulation_.n_active_cells());
  VectorTools::integrate_difference(*discretization_.mapping, dof_handler_, solution_, exact,
                                    per_cell, quadrature, VectorTools::L2_norm);
  const double l2 =
      VectorTools::compute_global_error(triangulation_, per_cell, VectorTools::L2_norm);
  VectorTools::integrate_difference(*discretization_.mapping, dof_handler_, solution_, exact,
                                    per_cell, quadrature, VectorTools::H1_seminorm);
  const double h1 =
      VectorTools::compute_global_error(triangulation_, per_cell, VectorTools::H1_seminorm);
  return {l2, h1};
}

std::pair<SymmetricTensor<2, 3>, SymmetricTensor<2, 3>>
LinearElasticity::mean_strain_stress() const {
  FEValues<3> fe_values(*discretization_.mapping, *discretization_.fe,
                        discretization_.cell_quadrature, update_gradients | update_JxW_values);
  const FEValuesExtractors::Vector displacement(0);
  std::vector<SymmetricTensor<2, 3>> strains(discretization_.cell_quadrature.size());
  SymmetricTensor<2, 3> strain_sum, stress_sum;
  double volume = 0;
  for (const auto& cell : dof_handler_.active_cell_iterators()) {
    fe_values.reinit(cell);
    fe_values[displacement].get_function_symmetric_gradients(solution_, strains);
    for (unsigned int q = 0; q < strains.size(); ++q) {
      strain_sum += strains[q] * fe_values.JxW(q);
      stress_sum += materials_[cell->material_id()].stress(strains[q]) * fe_values.JxW(q);
      volume += fe_values.JxW(q);
    }
  }
  return {strain_sum / volume, stress_sum / volume};
}

} // namespace plantar::fem
