#include "fem/nonlinear_sole.h"

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
  problem_.setup({{parameters_.attached_boundary, nullptr, {{true, true, true}}}});
  contact_dofs_ = problem_.boundary_nodes(parameters_.contact_boundary);
  if (contact_dofs_.empty())
    throw std::invalid_argument("NonlinearSole: contact boundary id " +
                                std::to_string(parameters_.contact_boundary) + " has no face");
  const auto points = problem_.support_points();
  for (const auto& node : contact_dofs_) {
    for (unsigned int d = 0; d < 3; ++d)
      if (problem_.constraints().is_constrained(node[d]))
        throw std::invalid_argument(
            "NonlinearSole: contact node at (" + std::to_string(points[node[0]][0]) + ", " +
            std::to_string(points[node[0]][1]) + ", " + std::to_string(points[node[0]][2]) +
            ") is also on the attached boundary");
    contact_positions_.push_back(points[node[0]]);
  }
  const unsigned int n = 3 * n_contacts();
  contact_displacement_.reinit(n);
  contact_force_.reinit(n);
  reference_displacement_.reinit(n);
  reference_force_.reinit(n);
  compute_compliance();
}

void NonlinearSole::gather_contact_displacements() {
  for (unsigned int k = 0; k < n_contacts(); ++k)
    for (unsigned int d = 0; d < 3; ++d)
      contact_displacement_(3 * k + d) = problem_.solution()(contact_dofs_[k][d]);
}

void NonlinearSole::compute_compliance() {
  problem_.factorize_tangent();
  const unsigned int n = 3 * n_contacts();
  compliance_.reinit(n, n);
  dealii::Vector<double> rhs(problem_.dof_handler().n_dofs()), x(rhs.size());
  for (unsigned int j = 0; j < n; ++j) {
    rhs = 0;
    rhs(contact_dofs_[j / 3][j % 3]) = 1;
    problem_.solve_tangent(rhs, x);
    for (unsigned int i = 0; i < n; ++i)
      compliance_(i, j) = x(contact_dofs_[i / 3][i % 3]);
  }
  double max_value = 0, max_asym = 0;
  for (unsigned int i = 0; i < n; ++i)
    for (unsigned int j = 0; j < n; ++j) {
      max_value = std::max(max_value, std::abs(compliance_(i, j)));
      max_asym = std::max(max_asym, std::abs(compliance_(i, j) - compliance_(j, i)));
    }
  for (unsigned int i = 0; i < n; ++i)
    for (unsigned int j = i + 1; j < n; ++j)
      compliance_(i, j) = compliance_(j, i) = 0.5 * (compliance_(i, j) + compliance_(j, i));
  raw_asymmetry_ = max_value > 0 ? max_asym / max_value : 0;
  if (!std::isfinite(max_value) || !(max_value > 0))
    throw std::runtime_error("NonlinearSole: tangent compliance is not finite or zero (max " +
                             std::to_string(max_value) + ")");
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

SoleUpdateReport NonlinearSole::update(const dealii::Vector<double>& forces) {
  SoleUpdateReport report = apply_contact_forces(forces);
  if (report.prediction_error > parameters_.recondensation_tolerance) {
    condense();
    report.recondensed = true;
  } else {
    max_tolerated_error_ = std::max(max_tolerated_error_, report.prediction_error);
  }
  return report;
}

} // namespace plantar::fem
