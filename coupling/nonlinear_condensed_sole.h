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
//
// Visco-hyperelastic regions (fem/visco_hyperelastic_law.h): update() is
// called once per time-loop step of sole.time_step (s). A sole is "deformed"
// when ||u_c|| of the last check exceeds check_tolerance times the largest of
// its checks. A check advances the internal variables over the time t elapsed
// since the last check: a creep of t - dt at the last check's forces (within
// the tolerance they held), then one step dt to the new forces (one Newton
// solve instead of two if one step elapsed or the sole is not deformed: then
// over dt only). Then d moves by the drift h, the creep of one loop step at
// fixed forces (fem::NonlinearSole::update); between checks d += h at every
// call (linear extrapolation of the creep; C_T unchanged). A creep at constant
// force is not seen by the force test, so a check also fires on time when the
// sole is deformed and both
//   r(t) = max over regions of sum_i beta_i (1 - exp(-t / tau_i)) > check_tolerance
// (the fraction of the isochoric stress the branches can relax in t: a bound
// of the relative creep; keeps beta = 0 from checking on round-off drifts) and
//   k ||h|| > check_tolerance ||u_c||
// (after k calls: the creep extrapolated since the last check against u_c of
// the last check; a relaxed sole, h -> 0, is not checked until its forces
// move). An undeformed sole is not checked on time: its creep is below the
// tolerance at the run's scale, and a Newton solve of a state at round-off
// cannot reach a relative tolerance.
// Energy: work() (the contact forces' work over the checks, work() below) minus
// stored_base_energy() (int W(F) dV of the base, long-term, law) is what the
// branches absorbed: dissipated or still held by the overstresses (they have
// no closed-form free energy for a general W_iso, docs/viscoelastic.md).

#include "fem/discretization.h"
#include "fem/hyperelastic_material_table.h"
#include "fem/nonlinear_sole.h"

#include <deal.II/grid/tria.h>
#include <deal.II/lac/vector.h>

#include <Eigen/Core>

#include <memory>
#include <vector>

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
  bool checked = false;      ///< a Newton solve of the sole was done
  bool recondensed = false;  ///< C_T and d changed
  bool offset_moved = false; ///< d changed (viscous regions: after every call with a drift)
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
  /// Checks fired by the time test (viscous regions), included in n_checks().
  int n_time_checks() const { return n_time_checks_; }
  /// Work of the contact forces on the sole since t = 0 (J): sum over the checks of
  /// (f_prev + f) / 2 . du (du = u_c - u_c,prev, df = f - f_prev), the trapezoid, plus for a
  /// sole without relaxing branches (all beta = 0) df . (C_T(u_c) df - du) / 6: exact for u_c
  /// quadratic along a linear force path (fem::NonlinearSole::tangent_response).
  double work() const { return work_; }
  /// int W(F) dV (J) of the base laws at the last Newton solve: the elastic (long-term) part
  /// of the stored energy. One cell loop (allocates; for the summary).
  double stored_base_energy() const;
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
  void compute_offset();
  double relaxation(double t) const; ///< r(t) above
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
  dealii::Vector<double> increment_, slope_; // f - f_checked and u'(1) of the work's quadrature
  Eigen::VectorXd checked_forces_;
  Eigen::VectorXd checked_displacements_;
  bool viscous_ = false;
  bool end_slope_ = false; // work() with the end-slope term (no relaxing branch)
  std::vector<std::vector<fem::ViscousBranch>> regions_; // branches of each viscous region
  double elapsed_ = 0;                                   // s since the last check (viscous regions)
  int calls_since_ = 0;                                  // update() calls since the last check
  double drift_norm_ = 0;                                // ||h|| of the last check
  double checked_norm_ = 0;                              // ||u_c|| of the last check
  double max_checked_norm_ = 0;                          // the largest ||u_c|| of the checks
  double work_ = 0;
  int n_checks_ = 0;
  int n_time_checks_ = 0;
  unsigned int newton_iterations_ = 0;
};

} // namespace plantar::coupling
