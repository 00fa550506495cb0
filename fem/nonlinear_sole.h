#pragma once
// A hyperelastic sole seen from its contact nodes: the nonlinear counterpart
// of coupling::CondensedSole (linear), for the contact coupling and the time
// loop (David et al. 2008, eq. 11, with the stiffness replaced by the tangent).
//
// State: the displacement u of the sole attached on its top face (u = 0) and
// loaded by nodal contact forces f_c on its bottom (contact) nodes.
//   condense():  C = [K_T(u)^-1]_cc, the tangent compliance at the current
//                state (3 n_c x 3 n_c, m/N, node-major: rows 3k..3k+2 are
//                x, y, z of contact node k; mesh frame), stored with the
//                contact displacements u_ref and forces f_ref of that state.
//   predict(f):  u_c ~ u_ref + C (f - f_ref)  (what the coupling uses).
//   apply_contact_forces(f): Newton solve of R(u) = f (total forces), from
//                the current state, with force sub-steps if Newton fails;
//                then the prediction error
//                  e = ||u_c - predict(f)||_2 / ||u_c - u_ref||_2
//                (relative error of the linearised contact displacements over
//                the change since the last condensation; 0 if no change).
//   update(f):   apply_contact_forces, and condense() again if
//                e > recondensation_tolerance. Counts re-condensations and
//                records the largest error that was tolerated.
// Visco-hyperelastic regions (fem/visco_hyperelastic_law.h): update(f) is one
// time step of length time_step() (set_time_step, e.g. the time since the last
// update): Newton from the committed internal variables, then advance() commits
// them, then the error control re-condenses as above (C is then the algorithmic
// tangent's compliance, the history committed), then u_ref is moved by the
// relaxation the next step causes at fixed forces (NonlinearElasticity::
// history_drift, one assembly and one back-substitution; exact for the linear
// law), so that predict() follows the creep. apply_contact_forces alone
// commits nothing. update(f, next_step) computes that drift for a next step of
// another length than time_step() (e.g. one time-loop step after an update
// that covered several); extrapolate_drift() moves u_ref by it once more (the
// creep of one more step at fixed forces, without a Newton solve).
// The full field (pressure condensed) is solution() of elasticity().
//
// Matrices are deal.II FullMatrix (row-major, contiguous; C is symmetric, so
// Eigen::Map<const Eigen::MatrixXd>(&C(0, 0), 3 n_c, 3 n_c) views it as the
// Eigen matrix of CondensedSole::compliance()).

#include "fem/nonlinear_elasticity.h"

#include <deal.II/lac/full_matrix.h>

#include <array>
#include <vector>

namespace plantar::fem {

struct NonlinearSoleParameters {
  dealii::types::boundary_id attached_boundary = 0; ///< "top": u = 0
  dealii::types::boundary_id contact_boundary = 1;  ///< "bottom": contact nodes
  NonlinearSettings newton;                         ///< formulation and Newton tolerances
  /// Re-condense when the prediction error exceeds this, range (0, inf); default 5 %.
  double recondensation_tolerance = 0.05;
  /// Force sub-step halvings allowed when Newton fails, range [0, 10].
  unsigned int max_substep_halvings = 4;
  /// Time step of update() (s) where the materials have viscous branches: > 0 there (required),
  /// ignored otherwise; range [0, inf).
  double time_step = 0;
  /// Throws std::invalid_argument naming the field, its value and the range.
  void validate() const;
};

struct SoleUpdateReport {
  NewtonReport newton;         ///< summed over sub-steps
  unsigned int substeps = 1;   ///< force sub-steps used
  double prediction_error = 0; ///< e (see above)
  bool recondensed = false;    ///< update() only
};

class NonlinearSole {
public:
  /// Sets up the problem (top attached) and condenses at u = 0 (not counted as
  /// a re-condensation). Referenced objects must outlive this one.
  /// @throws std::invalid_argument on bad parameters or a contact boundary without faces.
  NonlinearSole(const dealii::Triangulation<3>& triangulation, const Discretization& discretization,
                const HyperelasticMaterialTable& materials,
                const NonlinearSoleParameters& parameters = {});

  unsigned int n_contacts() const { return static_cast<unsigned int>(contact_dofs_.size()); }
  /// Reference positions of the contact nodes (m), node k.
  const std::vector<dealii::Point<3>>& contact_positions() const { return contact_positions_; }
  const std::vector<std::array<dealii::types::global_dof_index, 3>>& contact_dofs() const {
    return contact_dofs_;
  }

  /// Tangent compliance at the last condensation (3 n_c x 3 n_c, m/N), symmetrized.
  const dealii::FullMatrix<double>& compliance() const { return compliance_; }
  /// max |C - C^T| / max |C| before symmetrization.
  double raw_asymmetry() const { return raw_asymmetry_; }
  /// Recomputes C at the current state and counts a re-condensation.
  void condense();

  /// u_ref + C (f - f_ref) (3 n_c, m) for contact forces @p forces (3 n_c, N).
  void predict(const dealii::Vector<double>& forces, dealii::Vector<double>& displacements) const;
  /// Newton solve for the total contact forces @p forces (3 n_c, N, mesh frame).
  /// @throws std::runtime_error if Newton fails even with sub-steps (state restored).
  SoleUpdateReport apply_contact_forces(const dealii::Vector<double>& forces);
  /// apply_contact_forces, then (viscous regions) the internal variables committed, then
  /// condense() if the prediction error exceeds the tolerance.
  /// Viscous regions: the history drift is for a next step of @p next_step (s; 0: time_step()).
  /// @p error_control false: no re-condensation (e.g. an update that another follows at once).
  SoleUpdateReport update(const dealii::Vector<double>& forces, double next_step = 0,
                          bool error_control = true);
  /// Viscous regions: u_ref += the last update's drift (contact part), the creep of one more
  /// step of its length at fixed forces. No heap allocation.
  void extrapolate_drift();
  /// [K_T^-1 P f]_c: the contact displacements (3 n_c, m) that contact forces @p forces (3 n_c,
  /// N) add to first order, K_T the last factorized tangent (the last Newton iteration's, near
  /// the converged state, or the last condensation's). One back-substitution, no heap
  /// allocation.
  void tangent_response(const dealii::Vector<double>& forces,
                        dealii::Vector<double>& displacements);
  /// The contact part of the last update's drift (3 n_c, m; zero without viscous regions).
  const dealii::Vector<double>& contact_drift() const { return contact_drift_; }
  /// u_ref and f_ref of predict() (3 n_c; m, N).
  const dealii::Vector<double>& reference_displacements() const { return reference_displacement_; }
  const dealii::Vector<double>& reference_forces() const { return reference_force_; }
  /// The time step of the next update()s (s, > 0; viscous regions). Throws std::invalid_argument.
  void set_time_step(double dt) { problem_.set_time_step(dt); }
  double time_step() const { return problem_.time_step(); }

  /// Current contact displacements (3 n_c, m) and forces (N).
  const dealii::Vector<double>& contact_displacements() const { return contact_displacement_; }
  const dealii::Vector<double>& contact_forces() const { return contact_force_; }
  unsigned int n_recondensations() const { return n_recondensations_; }
  /// Largest prediction error seen without re-condensing, and the last one.
  double max_tolerated_error() const { return max_tolerated_error_; }
  double last_prediction_error() const { return last_error_; }

  /// The FEM problem; its solution() is the full displacement field (m).
  const NonlinearElasticity& elasticity() const { return problem_; }
  const NonlinearSoleParameters& parameters() const { return parameters_; }

private:
  void gather_contact_displacements();
  void compute_compliance();

  NonlinearSoleParameters parameters_;
  NonlinearElasticity problem_;
  std::vector<std::array<dealii::types::global_dof_index, 3>> contact_dofs_;
  std::vector<dealii::Point<3>> contact_positions_;
  dealii::FullMatrix<double> compliance_;
  double raw_asymmetry_ = 0;
  dealii::Vector<double> contact_displacement_, contact_force_;
  dealii::Vector<double> reference_displacement_, reference_force_;
  dealii::Vector<double> drift_;           // viscous regions: history_drift() of the last update
  dealii::Vector<double> contact_drift_;   // its contact part (3 n_c)
  dealii::Vector<double> load_, response_; // tangent_response() workspaces (dof order)
  unsigned int n_recondensations_ = 0;
  double max_tolerated_error_ = 0, last_error_ = 0;
};

} // namespace plantar::fem
