#include "coupling/nonlinear_condensed_sole.h"

#include <cmath>
#include <sstream>
#include <stdexcept>

namespace plantar::coupling {

void NonlinearCouplingParameters::validate() const {
  sole.validate();
  if (!(check_tolerance >= 0 && check_tolerance <= 1)) {
    std::ostringstream msg;
    msg << "NonlinearCouplingParameters.check_tolerance = " << check_tolerance
        << " is out of range: allowed [0, 1]";
    throw std::invalid_argument(msg.str());
  }
}

NonlinearCondensedSole::NonlinearCondensedSole(const dealii::Triangulation<3>& triangulation,
                                               const fem::HyperelasticMaterialTable& materials,
                                               unsigned int degree,
                                               const NonlinearCouplingParameters& parameters)
    : parameters_((parameters.validate(), parameters)), materials_(materials) {
  triangulation_.copy_triangulation(triangulation);
  const fem::CellKind kind = triangulation_.all_reference_cells_are_hyper_cube()
                                 ? fem::CellKind::hexahedron
                                 : fem::CellKind::tetrahedron;
  discretization_ = std::make_unique<fem::Discretization>(kind, degree);
  sole_ = std::make_unique<fem::NonlinearSole>(triangulation_, *discretization_, materials_,
                                               parameters_.sole);
  const int n = static_cast<int>(sole_->n_contacts());
  contact_positions_.resize(n, 3);
  for (int k = 0; k < n; ++k)
    for (int d = 0; d < 3; ++d)
      contact_positions_(k, d) = sole_->contact_positions()[k][d];
  compliance_.resize(3 * n, 3 * n);
  offset_.setZero(3 * n);
  force_buffer_.reinit(3 * n);
  checked_forces_.setZero(3 * n);
  copy_condensation();
}

NonlinearCondensedSole::~NonlinearCondensedSole() = default;

void NonlinearCondensedSole::copy_condensation() {
  const auto& c = sole_->compliance();
  const int size = static_cast<int>(compliance_.rows());
  for (int i = 0; i < size; ++i)
    for (int j = 0; j < size; ++j)
      compliance_(i, j) = c(i, j);
  // d = u_ref - C_T f_ref at the state of the condensation (the current one).
  Eigen::VectorXd u(size), f(size);
  for (int i = 0; i < size; ++i) {
    u[i] = sole_->contact_displacements()(i);
    f[i] = sole_->contact_forces()(i);
  }
  offset_ = u - compliance_ * f;
}

void NonlinearCondensedSole::check_size(const Eigen::Ref<const Eigen::VectorXd>& forces,
                                        const char* where) const {
  if (forces.size() != 3 * n_contacts()) {
    std::ostringstream msg;
    msg << "NonlinearCondensedSole::" << where << ": forces have " << forces.size()
        << " entries, expected 3 n_c = " << 3 * n_contacts();
    throw std::invalid_argument(msg.str());
  }
}

NonlinearUpdateReport
NonlinearCondensedSole::update(const Eigen::Ref<const Eigen::VectorXd>& forces) {
  check_size(forces, "update");
  NonlinearUpdateReport report;
  const double scale = std::max(forces.norm(), checked_forces_.norm());
  if ((forces - checked_forces_).norm() <= parameters_.check_tolerance * scale)
    return report;
  for (int i = 0; i < forces.size(); ++i)
    force_buffer_(i) = forces[i];
  const fem::SoleUpdateReport r = sole_->update(force_buffer_);
  checked_forces_ = forces;
  ++n_checks_;
  newton_iterations_ += r.newton.iterations;
  report.checked = true;
  report.recondensed = r.recondensed;
  report.newton_iterations = r.newton.iterations;
  report.prediction_error = r.prediction_error;
  if (r.recondensed)
    copy_condensation();
  return report;
}

const dealii::Vector<double>&
NonlinearCondensedSole::deformation_field(const Eigen::Ref<const Eigen::VectorXd>& forces) {
  check_size(forces, "deformation_field");
  if (forces != checked_forces_) {
    for (int i = 0; i < forces.size(); ++i)
      force_buffer_(i) = forces[i];
    const fem::SoleUpdateReport r = sole_->apply_contact_forces(force_buffer_);
    newton_iterations_ += r.newton.iterations;
    checked_forces_ = forces;
  }
  return sole_->elasticity().solution();
}

Eigen::VectorXd NonlinearCondensedSole::contact_displacements() const {
  const auto& u = sole_->contact_displacements();
  Eigen::VectorXd out(u.size());
  for (unsigned int i = 0; i < u.size(); ++i)
    out[i] = u(i);
  return out;
}

} // namespace plantar::coupling
