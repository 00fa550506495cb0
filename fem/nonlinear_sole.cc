#include "fem/nonlinear_sole.h"

#include "fem/contact_condensation.h"

#include <algorithm>
#include <cmath>
#include <sstream>
#include <stdexcept>

namespace plantar::fem {

void NonlinearSoleParameters::validate() const {
  newton.validate();
  std::ostringstream message;
  if (!(recondensation_tolerance > 0) || !std::isfinite(recondensation_tolerance))
    message << "NonlinearSoleParameters.recondensation_tolerance = " << recondensation_tolerance
            << " is out of range: allowed (0, inf)";
  else if (!(time_step >= 0) || !std::isfinite(time_step))
    message << "NonlinearSoleParameters.time_step = " << time_step
            << " s is out of range: allowed [0, inf)";
  else if (max_substep_halvings > 10)
    message << "NonlinearSoleParameters.max_substep_halvings = " << max_substep_halvings
            << " is out of range: allowed [0, 10]";
  else if (attached_boundary == contact_boundary)
    message << "NonlinearSoleParameters: attached_boundary and contact_boundary are both "
            << attached_boundary;
  if (!message.str().empty())
    throw std::invalid_argument(message.str());
}

NonlinearSole::NonlinearSole(const dealii::Triangulation<3>& triangulation,
                             const Discretization& discretization,
                             const HyperelasticMaterialTable& materials,
                             const NonlinearSoleParameters& parameters)
    : parameters_((parameters.validate(), parameters)),
      problem_(triangulation, discretization, materials, parameters.newton) {
  if (materials.has_viscosity()) {
    if (!(parameters_.time_step > 0))
      throw std::invalid_argument(
          "NonlinearSoleParameters.time_step = 0 s is out of range: the materials have viscous "
          "branches (allowed: > 0 s)");
    problem_.set_time_step(parameters_.time_step);
  }
  problem_.setup({{parameters_.attached_boundary, nullptr, {{true, true, true}}}});
  contact_dofs_ = problem_.boundary_nodes(parameters_.contact_boundary);
  if (contact_dofs_.empty())
    throw std::invalid_argument("NonlinearSole: contact boundary id " +
                                std::to_string(parameters_.contact_boundary) + " has no face");
  const auto points = problem_.support_points();
  check_contact_nodes_free(contact_dofs_, problem_.constraints(), points,
                           parameters_.attached_boundary, "NonlinearSole");
  for (const auto& node : contact_dofs_)
    contact_positions_.push_back(points[node[0]]);
  const unsigned int n = 3 * n_contacts();
  contact_displacement_.reinit(n);
  contact_force_.reinit(n);
  reference_displacement_.reinit(n);
  reference_force_.reinit(n);
  contact_drift_.reinit(n);
  load_.reinit(problem_.solution().size());
  response_.reinit(problem_.solution().size());
  compute_compliance();
}

void NonlinearSole::gather_contact_displacements() {
  for (unsigned int k = 0; k < n_contacts(); ++k)
    for (unsigned int d = 0; d < 3; ++d)
      contact_displacement_(3 * k + d) = problem_.solution()(contact_dofs_[k][d]);
}

void NonlinearSole::compute_compliance() {
  // C = [K_T^-1]_cc by unit-load solves with the UMFPACK factorization of K_T
  // (one right-hand side at a time, in deal.II's full dof numbering).
  problem_.factorize_tangent();
  const unsigned int n = 3 * n_contacts();
  const auto n_dofs = static_cast<unsigned int>(problem_.dof_handler().n_dofs());
  std::vector<unsigned int> contact_index(n);
  for (unsigned int i = 0; i < n; ++i)
    contact_index[i] = static_cast<unsigned int>(contact_dofs_[i / 3][i % 3]);
  dealii::Vector<double> rhs(n_dofs), x(n_dofs);
  const BlockSolve solve = [&](const double* b, double* solution, unsigned int count) {
    for (unsigned int j = 0; j < count; ++j) {
      std::copy(b + std::size_t{j} * n_dofs, b + std::size_t{j + 1} * n_dofs, rhs.begin());
      problem_.solve_tangent(rhs, x);
      std::copy(x.begin(), x.end(), solution + std::size_t{j} * n_dofs);
    }
  };
  compliance_.reinit(n, n);
  // FullMatrix is row-major: this stores C^T, which symmetrize() maps onto the same C.
  double* c = n > 0 ? &compliance_(0, 0) : nullptr;
  contact_block_of_inverse(contact_index, n_dofs, 1, solve, c, "NonlinearSole (tangent)");
  raw_asymmetry_ = relative_asymmetry(c, n);
  symmetrize(c, n);
  gather_contact_displacements();
  reference_displacement_ = contact_displacement_;
  reference_force_ = contact_force_;
}

void NonlinearSole::condense() {
  compute_compliance();
  ++n_recondensations_;
}

void NonlinearSole::predict(const dealii::Vector<double>& forces,
                            dealii::Vector<double>& displacements) const {
  const unsigned int n = 3 * n_contacts();
  if (forces.size() != n)
    throw std::invalid_argument("NonlinearSole::predict: forces has size " +
                                std::to_string(forces.size()) +
                                ", expected 3 n_c = " + std::to_string(n));
  dealii::Vector<double> increment(forces);
  increment -= reference_force_;
  displacements.reinit(n);
  compliance_.vmult(displacements, increment);
  displacements += reference_displacement_;
}

SoleUpdateReport NonlinearSole::apply_contact_forces(const dealii::Vector<double>& forces) {
  const unsigned int n = 3 * n_contacts();
  if (forces.size() != n)
    throw std::invalid_argument("NonlinearSole::apply_contact_forces: forces has size " +
                                std::to_string(forces.size()) +
                                ", expected 3 n_c = " + std::to_string(n));
  SoleUpdateReport report;
  const dealii::Vector<double> saved = problem_.solution();
  const dealii::Vector<double> start_force = contact_force_;
  std::string last_error;
  for (unsigned int halvings = 0; halvings <= parameters_.max_substep_halvings; ++halvings) {
    const unsigned int n_steps = 1u << halvings;
    problem_.solution() = saved;
    report = SoleUpdateReport();
    report.substeps = n_steps;
    try {
      for (unsigned int s = 1; s <= n_steps; ++s) {
        const double fraction = static_cast<double>(s) / n_steps;
        dealii::Vector<double>& load = problem_.nodal_load();
        load = 0;
        for (unsigned int i = 0; i < n; ++i)
          load(contact_dofs_[i / 3][i % 3]) =
              start_force(i) + fraction * (forces(i) - start_force(i));
        const NewtonReport step = problem_.solve_at(1.0);
        report.newton.iterations += step.iterations;
        report.newton.line_search_cuts += step.line_search_cuts;
        report.newton.final_residual = step.final_residual;
        report.newton.min_jacobian = step.min_jacobian;
        ++report.newton.load_steps;
      }
      last_error.clear();
      break;
    } catch (const std::runtime_error& e) {
      last_error = e.what();
    }
  }
  if (!last_error.empty()) {
    problem_.solution() = saved;
    throw std::runtime_error("NonlinearSole: contact forces not reached with " +
                             std::to_string(1u << parameters_.max_substep_halvings) +
                             " sub-steps: " + last_error);
  }
  contact_force_ = forces;
  gather_contact_displacements();
  dealii::Vector<double> predicted;
  predict(forces, predicted);
  dealii::Vector<double> change(contact_displacement_);
  change -= reference_displacement_;
  predicted -= contact_displacement_;
  const double change_norm = change.l2_norm();
  report.prediction_error = change_norm > 0 ? predicted.l2_norm() / change_norm : 0.0;
  last_error_ = report.prediction_error;
  return report;
}

SoleUpdateReport NonlinearSole::update(const dealii::Vector<double>& forces, double next_step,
                                       bool error_control) {
  SoleUpdateReport report = apply_contact_forces(forces);
  problem_.advance();
  if (error_control) {
    if (report.prediction_error > parameters_.recondensation_tolerance) {
      condense();
      report.recondensed = true;
    } else {
      max_tolerated_error_ = std::max(max_tolerated_error_, report.prediction_error);
    }
  }
  if (problem_.history() != nullptr) {
    // The relaxation over the next step at fixed forces moves the reference of the prediction.
    const double step = problem_.time_step();
    if (next_step > 0)
      problem_.set_time_step(next_step);
    problem_.history_drift(drift_);
    problem_.set_time_step(step);
    for (unsigned int i = 0; i < 3 * n_contacts(); ++i)
      contact_drift_(i) = drift_(contact_dofs_[i / 3][i % 3]);
    reference_displacement_ += contact_drift_;
  }
  return report;
}

void NonlinearSole::tangent_response(const dealii::Vector<double>& forces,
                                     dealii::Vector<double>& displacements) {
  const unsigned int n = 3 * n_contacts();
  if (forces.size() != n || displacements.size() != n)
    throw std::invalid_argument("NonlinearSole::tangent_response: forces and displacements have "
                                "sizes " +
                                std::to_string(forces.size()) + ", " +
                                std::to_string(displacements.size()) +
                                ", expected 3 n_c = " + std::to_string(n));
  load_ = 0;
  for (unsigned int i = 0; i < n; ++i)
    load_(contact_dofs_[i / 3][i % 3]) = forces(i);
  problem_.solve_tangent(load_, response_);
  for (unsigned int i = 0; i < n; ++i)
    displacements(i) = response_(contact_dofs_[i / 3][i % 3]);
}

void NonlinearSole::extrapolate_drift() {
  reference_displacement_ += contact_drift_;
}

} // namespace plantar::fem
