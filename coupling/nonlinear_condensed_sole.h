#pragma once
// A hyperelastic sole for the contact coupling: the nonlinear counterpart of
// CondensedSole. It owns a fem::NonlinearSole (mesh, laws, Newton) and gives
// the stepper an affine model of the contact-node displacements
//
//   u_c(f) ~ C_T f + d,   d = u_ref - C_T f_ref                      (1)
//
// C_T = [K_T(u_ref)^-1]_cc the tangent compliance at the last condensation
// (3 n_c x 3 n_c, m/N, sole frame, node-major) and (u_ref, f_ref) the contact
// displacements and forces of that state. At u = 0: C_T = C of the linear
// sole and d = 0, so (1) is CondensedSole's u_c = C f.
//
// After each time step, update(f) receives the contact forces on the nodes
// (3 n_c, N, sole frame). A Newton solve of the full sole at f (the "check")
// is done only when f moved by more than check_tolerance (relative) since the
// last check; it yields the exact u_c and the prediction error of (1)
//   e = ||u_c - (C_T f + d)|| / ||u_c - u_ref||
// and re-condenses (new C_T, d) when e > recondensation_tolerance
// (fem/nonlinear_sole.h). Small strains: e stays below the tolerance, C_T and
// d never change and the run costs the linear model plus the checks.
// The full deformation field at the forces of the last check (or any forces,
// deformation_field()) is available for output.

#include "fem/discretization.h"
#include "fem/hyperelastic_material_table.h"
#include "fem/nonlinear_sole.h"

#include <deal.II/grid/tria.h>
#include <deal.II/lac/vector.h>

#include <Eigen/Core>

#include <memory>

namespace plantar::coupling {

struct NonlinearCouplingParameters {
  fem::NonlinearSoleParameters sole; ///< boundaries, Newton, recondensation_tolerance
  /// Relative force change ||f - f_checked|| / max(||f||, ||f_checked||) above which update()
  /// runs a Newton check, range [0, 1]; 0 checks at every call.
  double check_tolerance = 0.02;
  /// Throws std::invalid_argument naming the field, its value and the range.
  void validate() const;
};

/// What one update() did.
struct NonlinearUpdateReport {
  bool checked = false;     ///< a Newton solve of the sole was done
  bool recondensed = false; ///< C_T and d changed
  unsigned int newton_iterations = 0;
  double prediction_error = 0; ///< e of eq. (1) at this check (0 if not checked)
};

class NonlinearCondensedSole {
public:
  /// Copies @p triangulation and @p materials; @p degree 1 or 2. Condenses at u = 0.
  /// @throws std::invalid_argument on bad parameters or boundaries.
  NonlinearCondensedSole(const dealii::Triangulation<3>& triangulation,
                         const fem::HyperelasticMaterialTable& materials, unsigned int degree,
                         const NonlinearCouplingParameters& parameters);
  ~NonlinearCondensedSole();

  int n_contacts() const { return static_cast<int>(contact_positions_.rows()); }
  /// Contact node positions (n_c x 3, m, sole frame); row k is node k of C_T and d.
  const Eigen::MatrixX3d& contact_positions() const { return contact_positions_; }
  /// C_T of eq. (1), (3 n_c x 3 n_c), m/N, sole frame, symmetric.
  const Eigen::MatrixXd& compliance() const { return compliance_; }
  /// d of eq. (1), (3 n_c), m, sole frame.
  const Eigen::VectorXd& offset() const { return offset_; }

  /// After a step: @p forces the contact forces on the nodes (3 n_c, N, sole frame).
  /// @throws std::invalid_argument on size; std::runtime_error if Newton fails (state kept).
  NonlinearUpdateReport update(const Eigen::Ref<const Eigen::VectorXd>& forces);

  int n_checks() const { return n_checks_; }
  unsigned int n_recondensations() const { return sole_->n_recondensations(); }
  /// Largest e accepted without re-condensing.
  double max_tolerated_error() const { return sole_->max_tolerated_error(); }
  unsigned int newton_iterations() const { return newton_iterations_; }

  /// Full displacement field (deal.II dof order, m) at @p forces: a Newton solve if they
  /// differ from the last check's (the sole's state then moves to them; C_T, d unchanged).
  const dealii::Vector<double>& deformation_field(const Eigen::Ref<const Eigen::VectorXd>& forces);
  /// Contact displacements of the last Newton solve (3 n_c, m, sole frame).
  Eigen::VectorXd contact_displacements() const;
  const fem::NonlinearSole& sole() const { return *sole_; }
  const NonlinearCouplingParameters& parameters() const { return parameters_; }

private:
  void copy_condensation();
  void check_size(const Eigen::Ref<const Eigen::VectorXd>& forces, const char* where) const;

  NonlinearCouplingParameters parameters_;
  dealii::Triangulation<3> triangulation_;
  fem::HyperelasticMaterialTable materials_;
  std::unique_ptr<fem::Discretization> discretization_;
  std::unique_ptr<fem::NonlinearSole> sole_;
  Eigen::MatrixX3d contact_positions_;
  Eigen::MatrixXd compliance_;
  Eigen::VectorXd offset_;
  dealii::Vector<double> force_buffer_;
  Eigen::VectorXd checked_forces_;
  int n_checks_ = 0;
  unsigned int newton_iterations_ = 0;
};

} // namespace plantar::coupling
