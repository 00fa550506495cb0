#include "coupling/nonlinear_condensed_sole.h"

#include <deal.II/fe/fe_values.h>

#include <cmath>
#include <limits>
#include <set>
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
  increment_.reinit(3 * n);
  slope_.reinit(3 * n);
  checked_forces_.setZero(3 * n);
  checked_displacements_.setZero(3 * n);
  viscous_ = materials_.has_viscosity();
  std::set<dealii::types::material_id> ids;
  for (const auto& cell : triangulation_.active_cell_iterators())
    ids.insert(cell->material_id());
  for (const dealii::types::material_id id : ids)
    if (const fem::ViscoHyperelasticLaw* law = materials_.viscous(id))
      regions_.push_back(law->branches());
  end_slope_ = relaxation(std::numeric_limits<double>::infinity()) == 0.0; // no branch relaxes
  copy_condensation();
}

NonlinearCondensedSole::~NonlinearCondensedSole() = default;

void NonlinearCondensedSole::copy_condensation() {
  const auto& c = sole_->compliance();
  const int size = static_cast<int>(compliance_.rows());
  for (int i = 0; i < size; ++i)
    for (int j = 0; j < size; ++j)
      compliance_(i, j) = c(i, j);
  compute_offset();
}

void NonlinearCondensedSole::compute_offset() {
  // d = u_ref - C_T f_ref (u_ref: the condensation's state, moved by the drifts since).
  const int size = static_cast<int>(compliance_.rows());
  for (int i = 0; i < size; ++i)
    offset_[i] = sole_->reference_displacements()(i);
  for (int i = 0; i < size; ++i) {
    const double f = sole_->reference_forces()(i);
    if (f != 0.0)
      offset_ -= compliance_.col(i) * f; // C_T symmetric
  }
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
  const double dt = parameters_.sole.time_step;
  if (viscous_)
    elapsed_ += dt;
  ++calls_since_;
  const double scale = std::max(forces.norm(), checked_forces_.norm());
  const bool force_moved = (forces - checked_forces_).norm() > parameters_.check_tolerance * scale;
  const double tolerance = parameters_.check_tolerance;
  // Deformed: u_c of the last check above the tolerance of the largest (else its creep is below
  // the run's scale, and a Newton solve of a state at round-off cannot reach the tolerance).
  const bool deformed = checked_norm_ > tolerance * max_checked_norm_;
  const bool crept = viscous_ && deformed && relaxation(elapsed_) > tolerance &&
                     calls_since_ * drift_norm_ > tolerance * checked_norm_;
  if (!force_moved && !crept) {
    if (viscous_ && drift_norm_ > 0) {
      // One more loop step of creep at fixed forces: d += h.
      sole_->extrapolate_drift();
      const auto& h = sole_->contact_drift();
      for (int i = 0; i < forces.size(); ++i)
        offset_[i] += h(i);
      report.offset_moved = true;
    }
    return report;
  }
  const auto& u = sole_->contact_displacements();
  if (viscous_ && elapsed_ > 1.5 * dt && deformed && relaxation(elapsed_ - dt) > 0) {
    // The forces stayed within the tolerance of the checked ones until the last step: the sole
    // crept at those forces for elapsed - dt, then the last step moves them. (A step over the
    // whole interval would assume forces linear in time over it: a sudden load would find the
    // branches relaxed.)
    for (int i = 0; i < forces.size(); ++i)
      force_buffer_(i) = checked_forces_[i];
    sole_->set_time_step(elapsed_ - dt);
    // No re-condensation here: the step to the new forces follows and judges the prediction.
    const fem::SoleUpdateReport creep = sole_->update(force_buffer_, dt, false);
    newton_iterations_ += creep.newton.iterations;
    for (int i = 0; i < forces.size(); ++i) {
      work_ += checked_forces_[i] * (u(i) - checked_displacements_[i]);
      checked_displacements_[i] = u(i);
    }
    elapsed_ = dt;
  }
  for (int i = 0; i < forces.size(); ++i)
    force_buffer_(i) = forces[i];
  if (viscous_) // an undeformed sole had nothing to relax
    sole_->set_time_step(deformed ? elapsed_ : dt);
  const fem::SoleUpdateReport r = sole_->update(force_buffer_, dt);
  // Work of the contact forces over the checked interval, f linear in s in [0, 1]: the trapezoid,
  // plus for an elastic sole the end-slope term df . (C_T df - du) / 6 (C_T df = u'(1)), exact for
  // u quadratic in s (the trapezoid alone errs by O(df^3) per interval on a stiffening sole:
  // large over a landing's few steps). With relaxing branches C_T is the algorithmic tangent of
  // the whole step, not the path's slope: the trapezoid alone (docs/viscoelastic.md).
  if (end_slope_) {
    for (int i = 0; i < forces.size(); ++i)
      increment_(i) = forces[i] - checked_forces_[i];
    sole_->tangent_response(increment_, slope_);
  }
  for (int i = 0; i < forces.size(); ++i) {
    const double du = u(i) - checked_displacements_[i];
    work_ += 0.5 * (checked_forces_[i] + forces[i]) * du;
    if (end_slope_)
      work_ += increment_(i) * (slope_(i) - du) / 6;
    checked_displacements_[i] = u(i);
  }
  checked_forces_ = forces;
  ++n_checks_;
  if (!force_moved)
    ++n_time_checks_;
  newton_iterations_ += r.newton.iterations;
  report.checked = true;
  report.recondensed = r.recondensed;
  report.newton_iterations = r.newton.iterations;
  report.prediction_error = r.prediction_error;
  if (r.recondensed)
    copy_condensation();
  else if (viscous_)
    compute_offset();
  report.offset_moved = r.recondensed || viscous_;
  if (viscous_) {
    elapsed_ = 0;
    drift_norm_ = sole_->contact_drift().l2_norm();
    checked_norm_ = u.l2_norm();
    max_checked_norm_ = std::max(max_checked_norm_, checked_norm_);
  }
  calls_since_ = 0;
  return report;
}

double NonlinearCondensedSole::relaxation(double t) const {
  double r = 0;
  for (const auto& branches : regions_) {
    double sum = 0;
    for (const fem::ViscousBranch& b : branches)
      sum -= b.beta * std::expm1(-t / b.relaxation_time);
    r = std::max(r, sum);
  }
  return r;
}

double NonlinearCondensedSole::stored_base_energy() const {
  const fem::NonlinearElasticity& problem = sole_->elasticity();
  const fem::Discretization& discretization = problem.discretization();
  dealii::FEValues<3> values(*discretization.mapping, *discretization.fe,
                             discretization.cell_quadrature,
                             dealii::update_gradients | dealii::update_JxW_values);
  const dealii::FEValuesExtractors::Vector displacement(0);
  std::vector<dealii::Tensor<2, 3>> gradients(discretization.cell_quadrature.size());
  double energy = 0;
  for (const auto& cell : problem.dof_handler().active_cell_iterators()) {
    values.reinit(cell);
    values[displacement].get_function_gradients(problem.solution(), gradients);
    const fem::HyperelasticLaw& law = problem.materials()[cell->material_id()];
    for (unsigned int q = 0; q < values.n_quadrature_points; ++q) {
      dealii::Tensor<2, 3> F = dealii::unit_symmetric_tensor<3>();
      F += gradients[q];
      energy += law.strain_energy(F) * values.JxW(q);
    }
  }
  return energy;
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
