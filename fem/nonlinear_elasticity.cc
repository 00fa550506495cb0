#include "fem/nonlinear_elasticity.h"

#include "fem/contact_condensation.h"

#include <deal.II/dofs/dof_tools.h>
#include <deal.II/fe/fe_values.h>
#include <deal.II/fe/mapping_fe.h>
#include <deal.II/grid/grid_tools.h>
#include <deal.II/lac/dynamic_sparsity_pattern.h>
#include <deal.II/lac/full_matrix.h>
#include <deal.II/numerics/vector_tools.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <functional>
#include <limits>
#include <map>
#include <sstream>
#include <stdexcept>

namespace plantar::fem {

using dealii::types::global_dof_index;

void NonlinearSettings::validate() const {
  std::ostringstream message;
  if (!(pressure_degree >= -1 && pressure_degree <= 1))
    message << "NonlinearSettings.pressure_degree = " << pressure_degree
            << " is out of range: allowed -1, 0, 1";
  else if (!(residual_tolerance > 0 && residual_tolerance < 1))
    message << "NonlinearSettings.residual_tolerance = " << residual_tolerance
            << " is out of range: allowed (0, 1)";
  else if (max_iterations < 1)
    message << "NonlinearSettings.max_iterations = " << max_iterations
            << " is out of range: allowed >= 1";
  if (!message.str().empty())
    throw std::invalid_argument(message.str());
}

NonlinearElasticity::NonlinearElasticity(const dealii::Triangulation<3>& triangulation,
                                         const Discretization& discretization,
                                         const HyperelasticMaterialTable& materials,
                                         const NonlinearSettings& settings)
    : triangulation_(triangulation), discretization_(discretization), materials_(materials),
      settings_(settings), dof_handler_(triangulation) {
  settings_.validate();
  pressure_degree_ = settings_.pressure_degree >= 0
                         ? settings_.pressure_degree
                         : (discretization.kind == CellKind::hexahedron
                                ? static_cast<int>(discretization.degree) - 1
                                : 0);
}

void NonlinearElasticity::setup(const std::vector<DirichletCondition>& dirichlet) {
  dof_handler_.distribute_dofs(*discretization_.fe);
  dirichlet_ = dirichlet;
  constraints_.clear();
  const dealii::Functions::ZeroFunction<3> zero(3);
  for (const auto& condition : dirichlet_) {
    const dealii::ComponentMask mask(
        std::vector<bool>(condition.components.begin(), condition.components.end()));
    dealii::VectorTools::interpolate_boundary_values(*discretization_.mapping, dof_handler_,
                                                     condition.boundary, zero, constraints_, mask);
  }
  constraints_.close();
  dealii::DynamicSparsityPattern dsp(dof_handler_.n_dofs());
  dealii::DoFTools::make_sparsity_pattern(dof_handler_, dsp, constraints_, false);
  sparsity_.copy_from(dsp);
  tangent_.reinit(sparsity_);
  const auto n = dof_handler_.n_dofs();
  solution_.reinit(n);
  residual_.reinit(n);
  newton_rhs_.reinit(n);
  internal_force_.reinit(n);
  traction_load_.reinit(n);
  nodal_load_.reinit(n);
  load_factor_ = 0;
  round_off_step_ = 1e3 * std::numeric_limits<double>::epsilon() *
                    dealii::GridTools::minimal_cell_diameter(triangulation_);
  history_.reset();
  if (materials_.has_viscosity())
    history_.emplace(triangulation_, materials_, discretization_.cell_quadrature.size());
}

void NonlinearElasticity::set_time_step(double dt) {
  if (!(dt > 0) || !std::isfinite(dt)) {
    std::ostringstream message;
    message << "NonlinearElasticity: time step dt = " << dt
            << " s is out of range: allowed (0, inf)";
    throw std::invalid_argument(message.str());
  }
  time_step_ = dt;
}

void NonlinearElasticity::advance() {
  if (!history_)
    return;
  assemble(false);
  history_->commit(time_step_);
}

void NonlinearElasticity::history_drift(dealii::Vector<double>& drift) {
  drift.reinit(solution_.size());
  if (!history_)
    return;
  assemble(false);
  newton_rhs_ = residual_; // scratch (newton_rhs_ is only read within solve_at)
  newton_rhs_ *= -1;
  solve_tangent(newton_rhs_, drift);
}

void NonlinearElasticity::reset_history() {
  if (history_)
    history_->reset();
}

void NonlinearElasticity::add_traction(dealii::types::boundary_id boundary,
                                       const dealii::Tensor<1, 3>& traction) {
  const auto& fe = *discretization_.fe;
  dealii::FEFaceValues<3> face_values(*discretization_.mapping, fe, discretization_.face_quadrature,
                                      dealii::update_values | dealii::update_JxW_values);
  std::vector<global_dof_index> dofs(fe.n_dofs_per_cell());
  bool found = false;
  for (const auto& cell : dof_handler_.active_cell_iterators())
    for (const unsigned int f : cell->face_indices())
      if (cell->face(f)->at_boundary() && cell->face(f)->boundary_id() == boundary) {
        found = true;
        face_values.reinit(cell, f);
        cell->get_dof_indices(dofs);
        for (unsigned int q = 0; q < face_values.n_quadrature_points; ++q)
          for (unsigned int i = 0; i < fe.n_dofs_per_cell(); ++i) {
            const unsigned int c = fe.system_to_component_index(i).first;
            traction_load_(dofs[i]) +=
                face_values.shape_value(i, q) * traction[c] * face_values.JxW(q);
          }
      }
  if (!found)
    throw std::invalid_argument("add_traction: boundary id " + std::to_string(boundary) +
                                " has no face");
}

void NonlinearElasticity::apply_dirichlet_values(double load_factor) {
  for (const auto& condition : dirichlet_) {
    if (condition.displacement == nullptr)
      continue;
    std::map<global_dof_index, double> values;
    const dealii::ComponentMask mask(
        std::vector<bool>(condition.components.begin(), condition.components.end()));
    dealii::VectorTools::interpolate_boundary_values(*discretization_.mapping, dof_handler_,
                                                     condition.boundary, *condition.displacement,
                                                     values, mask);
    for (const auto& [dof, value] : values)
      solution_(dof) = load_factor * value;
  }
  // Zero-valued conditions keep u = 0 (never changed by the homogeneous updates).
}

void NonlinearElasticity::assemble(bool with_tangent,
                                   const dealii::AffineConstraints<double>* predictor) {
  const auto& fe = *discretization_.fe;
  const unsigned int n_q = discretization_.cell_quadrature.size();
  const unsigned int n_dofs_cell = fe.n_dofs_per_cell();
  const bool mixed = settings_.formulation == NonlinearSettings::Formulation::mixed;
  const unsigned int n_p = mixed ? (pressure_degree_ == 0 ? 1 : 4) : 0;
  dealii::FEValues<3> fe_values(*discretization_.mapping, fe, discretization_.cell_quadrature,
                                dealii::update_gradients | dealii::update_JxW_values |
                                    dealii::update_quadrature_points);
  dealii::FullMatrix<double> cell_matrix(n_dofs_cell, n_dofs_cell);
  dealii::Vector<double> cell_rhs(n_dofs_cell), cell_internal(n_dofs_cell);
  std::vector<global_dof_index> dofs(n_dofs_cell);
  std::vector<std::vector<dealii::Tensor<1, 3>>> grad_u(n_q, std::vector<dealii::Tensor<1, 3>>(3));
  std::vector<dealii::Tensor<2, 3>> F(n_q);
  std::vector<double> J(n_q);
  std::vector<StressTangent> st(n_q);
  std::vector<unsigned int> component(n_dofs_cell);
  for (unsigned int i = 0; i < n_dofs_cell; ++i)
    component[i] = fe.system_to_component_index(i).first;
  // Mixed workspace.
  dealii::FullMatrix<double> M(n_p, n_p), M_inv(n_p, n_p), M_U(n_p, n_p), G(n_p, n_dofs_cell),
      MG(n_p, n_dofs_cell), T(n_p, n_dofs_cell);
  std::vector<std::array<double, 4>> phi(n_q);
  dealii::Vector<double> g(n_p), h(n_p), coeff(n_p);
  std::vector<double> J_tilde(n_q), pressure(n_q);

  residual_ = 0;
  internal_force_ = 0;
  if (predictor != nullptr)
    newton_rhs_ = 0;
  if (with_tangent)
    tangent_ = 0;
  double min_J = std::numeric_limits<double>::infinity();
  if (history_ && !(time_step_ > 0))
    throw std::invalid_argument("NonlinearElasticity: the materials have viscous branches: set "
                                "the time step (set_time_step(dt), dt > 0 s) before solving");

  for (const auto& cell : dof_handler_.active_cell_iterators()) {
    fe_values.reinit(cell);
    cell->get_dof_indices(dofs);
    const HyperelasticLaw& law = materials_[cell->material_id()];
    for (unsigned int q = 0; q < n_q; ++q) {
      dealii::Tensor<2, 3> grad;
      for (unsigned int i = 0; i < n_dofs_cell; ++i) {
        const auto dN = fe_values.shape_grad(i, q);
        for (unsigned int d = 0; d < 3; ++d)
          grad[component[i]][d] += solution_(dofs[i]) * dN[d];
      }
      F[q] = dealii::unit_symmetric_tensor<3>() + grad;
      J[q] = dealii::determinant(F[q]);
      min_J = std::min(min_J, J[q]);
      if (!(J[q] > 0))
        throw std::runtime_error("element " + std::to_string(cell->active_cell_index()) +
                                 " inverted: det F = " + std::to_string(J[q]) +
                                 " (allowed > 0) at load factor " + std::to_string(load_factor_));
      if (history_ && history_->is_viscous(cell->active_cell_index()))
        history_->evaluate(cell->active_cell_index(), q, F[q], !mixed, time_step_, st[q]);
      else
        law.evaluate(F[q], !mixed, st[q]);
    }

    if (mixed) {
      const dealii::Point<3> center = cell->center();
      const double scale = 1.0 / cell->diameter();
      M = 0;
      g = 0;
      for (unsigned int q = 0; q < n_q; ++q) {
        const auto x = fe_values.quadrature_point(q);
        phi[q] = {1.0, (x[0] - center[0]) * scale, (x[1] - center[1]) * scale,
                  (x[2] - center[2]) * scale};
        for (unsigned int a = 0; a < n_p; ++a) {
          g(a) += phi[q][a] * J[q] * fe_values.JxW(q);
          for (unsigned int b = 0; b < n_p; ++b)
            M(a, b) += phi[q][a] * phi[q][b] * fe_values.JxW(q);
        }
      }
      M_inv.invert(M);
      M_inv.vmult(coeff, g);
      for (unsigned int q = 0; q < n_q; ++q) {
        J_tilde[q] = 0;
        for (unsigned int a = 0; a < n_p; ++a)
          J_tilde[q] += coeff(a) * phi[q][a];
        if (!(J_tilde[q] > 0))
          throw std::runtime_error("element " + std::to_string(cell->active_cell_index()) +
                                   ": projected dilatation J~ = " + std::to_string(J_tilde[q]) +
                                   " (allowed > 0)");
      }
      h = 0;
      M_U = 0;
      for (unsigned int q = 0; q < n_q; ++q)
        for (unsigned int a = 0; a < n_p; ++a) {
          h(a) += phi[q][a] * law.volumetric_stress(J_tilde[q]) * fe_values.JxW(q);
          for (unsigned int b = 0; b < n_p; ++b)
            M_U(a, b) +=
                phi[q][a] * law.volumetric_tangent(J_tilde[q]) * phi[q][b] * fe_values.JxW(q);
        }
      M_inv.vmult(coeff, h);
      G = 0;
      for (unsigned int q = 0; q < n_q; ++q) {
        pressure[q] = 0;
        for (unsigned int a = 0; a < n_p; ++a)
          pressure[q] += coeff(a) * phi[q][a];
        const dealii::Tensor<2, 3> JFinvT = J[q] * dealii::transpose(dealii::invert(F[q]));
        const dealii::Tensor<2, 3> FinvT = JFinvT / J[q];
        // Volumetric stress and the geometric part of its tangent.
        st[q].first_piola += pressure[q] * JFinvT;
        for (unsigned int i = 0; i < 3; ++i)
          for (unsigned int I = 0; I < 3; ++I)
            for (unsigned int k = 0; k < 3; ++k)
              for (unsigned int L = 0; L < 3; ++L)
                st[q].tangent[i][I][k][L] +=
                    pressure[q] * J[q] * (FinvT[i][I] * FinvT[k][L] - FinvT[i][L] * FinvT[k][I]);
        if (with_tangent)
          for (unsigned int i = 0; i < n_dofs_cell; ++i) {
            const auto dN = fe_values.shape_grad(i, q);
            double value = 0;
            for (unsigned int d = 0; d < 3; ++d)
              value += JFinvT[component[i]][d] * dN[d];
            for (unsigned int a = 0; a < n_p; ++a)
              G(a, i) += phi[q][a] * value * fe_values.JxW(q);
          }
      }
    }

    cell_rhs = 0;
    if (with_tangent)
      cell_matrix = 0;
    for (unsigned int q = 0; q < n_q; ++q) {
      const double JxW = fe_values.JxW(q);
      const auto& P = st[q].first_piola;
      const auto& A = st[q].tangent;
      for (unsigned int i = 0; i < n_dofs_cell; ++i) {
        const auto dNi = fe_values.shape_grad(i, q);
        const unsigned int ci = component[i];
        cell_rhs(i) += (P[ci] * dNi) * JxW;
        if (!with_tangent)
          continue;
        // B[k][L] = sum_J dNi_J A[ci][J][k][L]
        dealii::Tensor<2, 3> B;
        for (unsigned int Jd = 0; Jd < 3; ++Jd)
          B += dNi[Jd] * A[ci][Jd];
        for (unsigned int j = 0; j < n_dofs_cell; ++j)
          cell_matrix(i, j) += (B[component[j]] * fe_values.shape_grad(j, q)) * JxW;
      }
    }
    if (mixed && with_tangent) {
      // K += G^T M^-1 M_U M^-1 G
      M_inv.mmult(MG, G);
      M_U.mmult(T, MG);
      MG.Tmmult(cell_matrix, T, true);
    }
    for (unsigned int i = 0; i < n_dofs_cell; ++i)
      internal_force_(dofs[i]) += cell_rhs(i);
    // Residual R = f_int - lambda f_ext: the external part is added below.
    if (predictor != nullptr) {
      // Newton right-hand side -R with the Dirichlet increments moved over (-K_ID g).
      constraints_.distribute_local_to_global(cell_rhs, dofs, residual_);
      cell_rhs *= -1;
      predictor->distribute_local_to_global(cell_matrix, cell_rhs, dofs, tangent_, newton_rhs_);
    } else if (with_tangent) {
      constraints_.distribute_local_to_global(cell_matrix, cell_rhs, dofs, tangent_, residual_);
    } else {
      constraints_.distribute_local_to_global(cell_rhs, dofs, residual_);
    }
  }
  for (unsigned int i = 0; i < residual_.size(); ++i)
    if (!constraints_.is_constrained(i)) {
      residual_(i) -= load_factor_ * (traction_load_(i) + nodal_load_(i));
      if (predictor != nullptr)
        newton_rhs_(i) += load_factor_ * (traction_load_(i) + nodal_load_(i));
    }
  min_jacobian_ = min_J;
}

void NonlinearElasticity::factorize_tangent() {
  assemble(true);
  factorization_.initialize(tangent_);
}

void NonlinearElasticity::solve_tangent(const dealii::Vector<double>& rhs,
                                        dealii::Vector<double>& x) const {
  x = rhs;
  for (unsigned int i = 0; i < x.size(); ++i)
    if (constraints_.is_constrained(i))
      x(i) = 0;
  factorization_.solve(x);
  constraints_.distribute(x);
}

NewtonReport NonlinearElasticity::solve_at(double load_factor) {
  NewtonReport report;
  report.load_steps = 1;
  load_factor_ = load_factor;
  const auto n = solution_.size();
  // Predictor: the first Newton step moves the Dirichlet dofs to lambda g and
  // the others by the linearised response (K_II du_I = -R_I - K_ID du_D).
  const dealii::Vector<double> start_state = solution_;
  apply_dirichlet_values(load_factor);
  dealii::Vector<double> target = solution_;
  solution_ = start_state;
  dealii::AffineConstraints<double> predictor;
  for (unsigned int i = 0; i < n; ++i)
    if (constraints_.is_constrained(i)) {
      predictor.add_line(i);
      predictor.set_inhomogeneity(i, target(i) - start_state(i));
    }
  predictor.close();
  assemble(true, &predictor);
  factorization_.initialize(tangent_);
  dealii::Vector<double> step(n), start(n), rhs(n);
  step = newton_rhs_;
  factorization_.solve(step);
  predictor.distribute(step);
  double free_rhs_norm = 0;
  for (unsigned int i = 0; i < n; ++i)
    if (!constraints_.is_constrained(i))
      free_rhs_norm += newton_rhs_(i) * newton_rhs_(i);
  double external_norm = 0;
  for (unsigned int i = 0; i < n; ++i)
    if (!constraints_.is_constrained(i))
      external_norm += std::pow(load_factor * (traction_load_(i) + nodal_load_(i)), 2);
  const double tolerance =
      settings_.residual_tolerance * std::max(std::sqrt(free_rhs_norm), std::sqrt(external_norm));
  if (!(tolerance > 0)) { // nothing to do: no load and no Dirichlet change
    assemble(false);
    report.final_residual = residual_norm();
    report.min_jacobian = min_jacobian_;
    return report;
  }
  double norm = std::numeric_limits<double>::infinity();
  bool first = true;
  while (true) {
    if (!first) {
      if (norm <= tolerance)
        break;
      if (report.iterations >= settings_.max_iterations) {
        std::ostringstream message;
        message << "Newton did not converge at load factor " << load_factor << ": "
                << report.iterations << " iterations, ||R|| = " << norm << " > tolerance "
                << tolerance;
        throw std::runtime_error(message.str());
      }
      factorization_.initialize(tangent_);
      rhs = residual_;
      rhs *= -1;
      solve_tangent(rhs, step);
      // At round-off the residual stagnates above a tolerance relative to a tiny load; the
      // update then says the state is converged.
      if (step.linfty_norm() <= round_off_step_)
        break;
    }
    start = solution_;
    double alpha = 1;
    bool accepted = false;
    for (unsigned int cut = 0; cut <= settings_.max_line_search; ++cut) {
      solution_ = start;
      solution_.add(alpha, step);
      if (first) // Dirichlet dofs always at their target
        for (unsigned int i = 0; i < n; ++i)
          if (constraints_.is_constrained(i))
            solution_(i) = target(i);
      try {
        assemble(true);
        const double trial = residual_norm();
        if (std::isfinite(trial) &&
            (first || trial < (1 - 1e-4 * alpha) * norm || trial <= tolerance)) {
          norm = trial;
          accepted = true;
          break;
        }
      } catch (const std::runtime_error&) {
        // inverted element: shorten the step
      }
      alpha *= 0.5;
      ++report.line_search_cuts;
    }
    ++report.iterations;
    if (std::getenv("PLANTAR_NEWTON_TRACE"))
      std::fprintf(stderr, "  newton %u: alpha %.3g ||R|| %.3e (tol %.3e) |du| %.3e (floor %.3e)\n",
                   report.iterations, alpha, norm, tolerance, step.linfty_norm(), round_off_step_);
    if (!accepted) {
      if (first) {
        solution_ = start_state;
        std::ostringstream message;
        message << "Newton predictor inverts elements at load factor " << load_factor
                << " (use more load steps)";
        throw std::runtime_error(message.str());
      }
      // Near round-off the residual may stagnate: accept the full step if it is small.
      solution_ = start;
      solution_.add(1.0, step);
      assemble(true);
      norm = residual_norm();
      if (!(norm <= 10 * tolerance)) {
        std::ostringstream message;
        message << "Newton line search failed at load factor " << load_factor << " (iteration "
                << report.iterations << ", ||R|| = " << norm << ", tolerance " << tolerance << ")";
        throw std::runtime_error(message.str());
      }
      break;
    }
    first = false;
  }
  report.final_residual = norm;
  report.min_jacobian = min_jacobian_;
  return report;
}

NewtonReport NonlinearElasticity::solve(unsigned int n_load_steps) {
  if (n_load_steps < 1)
    throw std::invalid_argument("solve: n_load_steps = 0 is out of range: allowed >= 1");
  solution_ = 0;
  NewtonReport total;
  for (unsigned int s = 1; s <= n_load_steps; ++s) {
    const NewtonReport step = solve_at(static_cast<double>(s) / n_load_steps);
    total.iterations += step.iterations;
    total.line_search_cuts += step.line_search_cuts;
    total.final_residual = step.final_residual;
    total.min_jacobian = step.min_jacobian;
    ++total.load_steps;
  }
  return total;
}

// K(0) v (unconstrained rows, N) by a central difference of the internal force
// at +-eps v: exact for the linear part, the O(eps^2) remainder is below round-off.
static void
tangent_product_at_zero(const std::function<void(const dealii::Vector<double>&)>& assemble_at,
                        const dealii::Vector<double>& internal_force,
                        const dealii::Vector<double>& v, dealii::Vector<double>& out) {
  out.reinit(v.size());
  if (v.linfty_norm() == 0)
    return;
  const double eps = 1e-7 / v.linfty_norm();
  dealii::Vector<double> state(v);
  state *= eps;
  assemble_at(state);
  dealii::Vector<double> plus = internal_force;
  state *= -1;
  assemble_at(state);
  for (unsigned int i = 0; i < out.size(); ++i)
    out(i) = (plus(i) - internal_force(i)) / (2 * eps);
}

void NonlinearElasticity::solve_linearized() {
  solution_ = 0;
  load_factor_ = 1;
  assemble(true);
  factorization_.initialize(tangent_);
  apply_dirichlet_values(1.0);
  const dealii::Vector<double> u_dirichlet = solution_;
  auto assemble_at = [this](const dealii::Vector<double>& state) {
    solution_ = state;
    assemble(false);
  };
  // K du = F - K u_D on the free dofs, du = 0 on the constrained ones.
  dealii::Vector<double> product;
  tangent_product_at_zero(assemble_at, internal_force_, u_dirichlet, product);
  dealii::Vector<double> rhs(solution_.size());
  for (unsigned int i = 0; i < rhs.size(); ++i)
    if (!constraints_.is_constrained(i))
      rhs(i) = traction_load_(i) + nodal_load_(i) - product(i);
  dealii::Vector<double> du(solution_.size());
  solve_tangent(rhs, du);
  du += u_dirichlet;
  // Internal force of the linear problem, K u (for reaction_force()).
  tangent_product_at_zero(assemble_at, internal_force_, du, product);
  solution_ = du;
  internal_force_ = product;
  min_jacobian_ = 1; // small-strain solution: the reference configuration
}

std::vector<std::array<global_dof_index, 3>>
NonlinearElasticity::boundary_nodes(dealii::types::boundary_id boundary) const {
  return fem::boundary_nodes(dof_handler_, boundary);
}

std::vector<dealii::Point<3>> NonlinearElasticity::support_points() const {
  std::vector<dealii::Point<3>> points(dof_handler_.n_dofs());
  dealii::DoFTools::map_dofs_to_support_points(*discretization_.mapping, dof_handler_, points);
  return points;
}

dealii::Tensor<1, 3>
NonlinearElasticity::reaction_force(dealii::types::boundary_id boundary) const {
  dealii::Tensor<1, 3> force;
  for (const auto& node : boundary_nodes(boundary))
    for (unsigned int d = 0; d < 3; ++d)
      force[d] += internal_force_(node[d]) -
                  load_factor_ * (traction_load_(node[d]) + nodal_load_(node[d]));
  return force;
}

double NonlinearElasticity::min_jacobian() const {
  return min_jacobian_;
}

double NonlinearElasticity::max_displacement() const {
  double result = 0;
  const auto& fe = *discretization_.fe;
  std::vector<global_dof_index> dofs(fe.n_dofs_per_cell());
  for (const auto& cell : dof_handler_.active_cell_iterators()) {
    cell->get_dof_indices(dofs);
    for (unsigned int i = 0; i < dofs.size(); ++i)
      if (fe.system_to_component_index(i).first == 0) {
        double norm2 = 0;
        for (unsigned int d = 0; d < 3; ++d)
          norm2 += solution_(dofs[i + d]) * solution_(dofs[i + d]);
        result = std::max(result, std::sqrt(norm2));
      }
  }
  return result;
}

dealii::Tensor<1, 3> NonlinearElasticity::displacement_at(const dealii::Point<3>& point) const {
  dealii::Vector<double> value(3);
  dealii::VectorTools::point_value(*discretization_.mapping, dof_handler_, solution_, point, value);
  return dealii::Tensor<1, 3>({value(0), value(1), value(2)});
}

} // namespace plantar::fem
