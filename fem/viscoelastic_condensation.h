#pragma once
// A linear viscoelastic (generalized Maxwell, fem/viscoelastic_material.h) sole condensed onto
// its contact nodes, exactly, at a fixed time step dt.
//
// Per step the recursive update gives sigma^{n+1} = C_eff : eps^{n+1} + s^n per quadrature point
// (s^n the history stress, known before the step), so the discrete equilibrium is
//
//   K_eff u^{n+1} = P f^{n+1} - f_h^n,   K_eff = int B^T C_eff B,   f_h^n = int B^T s^n,
//
// with K_eff constant (dt fixed; regions relaxing differently included) and P f the contact
// node forces. Condensed onto the contact dofs c (node-major, fem/contact_condensation.h):
//
//   u_c^{n+1} = C_eff f^{n+1} + d^n,   C_eff = [K_eff^-1]_cc,   d^n = -[K_eff^-1 f_h^n]_c,
//
// no approximation. C_eff is condensed once (unit-load solves with one sparse LU of K_eff,
// UMFPACK); d^n, the history displacement, is one back-substitution per step with the same
// factorization. advance(f) solves the full field for the step's forces, updates the internal
// variables per quadrature point, assembles f_h and computes d for the next step. Attached
// nodes are clamped (u = 0); no body force. Heap allocation happens only in the constructor.
//
// The contact-space form (separable sole, cell dissipation not asked for). When every region's
// branches are proportional to its effective tensor, C_ri = beta_i C_eff,r with beta_i, e_i and
// gamma_i shared by all regions (one relaxation spectrum and one branch Poisson ratio per
// region: law=prony with E<i>), the recursive update is h_i = C_i : eps(q_i) with the nodal
// history q_i^{n+1} = e_i q_i^n + gamma_i (u^{n+1} - u^n), and K_i = beta_i K_eff gives
// K_eff^-1 f_h^n = sum_i beta_i (e_i q_i^n - gamma_i u^n). Then u = K_eff^-1 P a and
// q_i = K_eff^-1 P b_i with contact-space vectors (3 n_c, N) following
//
//   a^{n+1} = f^{n+1} - sum_i beta_i (e_i b_i^n - gamma_i a^n),
//   b_i^{n+1} = e_i b_i^n + gamma_i (a^{n+1} - a^n),
//
// and u_c = C_eff a, q_c,i = C_eff b_i, d^n = -sum_i beta_i (e_i q_c,i^n - gamma_i u_c^n): one
// product with C_eff and O(n_c) work per step, no solve and no cell loop, the same arithmetic
// as the quadrature form up to round-off. The energies are quadratic forms in these vectors;
// the full fields are recovered on demand (one back-substitution for u, one per branch for
// the overstresses). Not available: the energy dissipated per cell (a sum over the steps of
// each cell's quadratic form).

#include "fem/discretization.h"
#include "fem/viscoelastic_cell_fields.h"
#include "fem/viscoelastic_material.h"

#include <deal.II/base/point.h>
#include <deal.II/base/symmetric_tensor.h>
#include <deal.II/dofs/dof_handler.h>
#include <deal.II/grid/tria.h>
#include <deal.II/lac/affine_constraints.h>
#include <deal.II/lac/vector.h>

#include <array>
#include <map>
#include <memory>
#include <vector>

namespace plantar::fem {

struct ViscoelasticCondensationParameters {
  dealii::types::boundary_id attached_boundary = 0; ///< clamped face (u = 0)
  dealii::types::boundary_id contact_boundary = 1;  ///< its nodes are the contact nodes
  double time_step = 1e-3;                          ///< dt (s), > 0, fixed
  unsigned int block_size = 64; ///< right-hand sides per condensation block, [1, 4096]
  /// Accumulate the energy dissipated per cell at every step (cell_dissipated_energy(), the
  /// .vtu field). false: a separable sole (above) is advanced in contact space.
  bool cell_dissipation = true;
  /// Throws std::invalid_argument naming the field, its value and the range.
  void validate() const;
};

/// Wall-clock seconds of the last advance() and of the set-up.
struct ViscoelasticTimings {
  double assembly = 0;      ///< set-up: dofs, K_eff
  double factorization = 0; ///< set-up: LU of K_eff
  double condensation = 0;  ///< set-up: the 3 n_c unit-load solves
  double field_solve = 0;   ///< last step: K_eff u = P f - f_h (one back-substitution)
  double history = 0;       ///< last step: internal variables, f_h, d (cell loop + one solve)
};

class ViscoelasticCondensation {
public:
  /// Builds the problem on @p triangulation with @p discretization and @p materials (all three
  /// referenced: they must outlive this object), assembles K_eff(dt), factorizes and condenses
  /// it. State: at rest (u = 0, h = 0).
  /// @throws std::invalid_argument on parameters, a boundary id without faces, or a contact
  ///   node on the attached face; std::runtime_error if K_eff is singular.
  ViscoelasticCondensation(const dealii::Triangulation<3>& triangulation,
                           const Discretization& discretization,
                           const ViscoelasticMaterialTable& materials,
                           const ViscoelasticCondensationParameters& parameters);
  ~ViscoelasticCondensation();
  ViscoelasticCondensation(const ViscoelasticCondensation&) = delete;
  ViscoelasticCondensation& operator=(const ViscoelasticCondensation&) = delete;

  unsigned int n_contacts() const { return static_cast<unsigned int>(contact_dofs_.size()); }
  unsigned int n_dofs() const;
  /// Contact node positions (m, mesh frame), node k at entry k.
  const std::vector<dealii::Point<3>>& contact_positions() const { return contact_positions_; }
  /// Global dofs (x, y, z) of contact node k.
  const std::vector<std::array<dealii::types::global_dof_index, 3>>& contact_dofs() const {
    return contact_dofs_;
  }

  /// C_eff = [K_eff(dt)^-1]_cc: (3 n_c)^2 doubles, row-major (symmetric), m/N, mesh frame,
  /// node-major. Constant.
  const std::vector<double>& effective_compliance() const { return compliance_; }
  /// max |C - C^T| / max |C| before symmetrization.
  double raw_asymmetry() const { return raw_asymmetry_; }

  /// d^n (3 n_c, m): the contact-node displacement at the end of the next step if the contact
  /// forces of that step were zero: u_c^{n+1} = C_eff f^{n+1} + d^n.
  const dealii::Vector<double>& history_displacement() const { return history_displacement_; }

  /// One step t_n -> t_n + dt under the contact forces @p contact_forces (3 n_c, N, mesh frame,
  /// node-major, at t_{n+1}): solves K_eff u^{n+1} = P f - f_h^n, updates h_i at every
  /// quadrature point (the recursive update above), assembles f_h^{n+1} and d^{n+1}.
  /// @p contact_displacement, optional (3 n_c, m, mesh frame, node-major): u_c^{n+1} =
  /// C_eff f^{n+1} + d^n as the caller's contact solve already has it; in the contact-space form
  /// it stands for the step's C_eff a^{n+1} (equal up to round-off), so that the step makes no
  /// product with C_eff; the quadrature form ignores it.
  /// No heap allocation. Throws std::invalid_argument on a size mismatch.
  void advance(const dealii::Vector<double>& contact_forces,
               const dealii::Vector<double>* contact_displacement = nullptr);
  /// Back to rest: u = 0, h = 0, d = 0, t = 0.
  void reset();

  /// u^{n} on the contact dofs (3 n_c, m) after the last advance().
  const dealii::Vector<double>& contact_displacement() const { return contact_displacement_; }
  /// The full field u^{n} (n_dofs, deal.II dof order, m); in the contact-space form recovered
  /// at the first call after a step (one back-substitution).
  const dealii::Vector<double>& solution() const;
  double time() const { return time_; }                      ///< t_n, s
  double time_step() const { return parameters_.time_step; } ///< dt, s
  const dealii::DoFHandler<3>& dof_handler() const { return dof_handler_; }
  const dealii::AffineConstraints<double>& constraints() const { return constraints_; }
  const ViscoelasticTimings& timings() const { return timings_; }
  /// Number of internal-variable tensors h_i stored (cells x quadrature points x branches; 0
  /// in the contact-space form).
  std::size_t n_internal_variables() const { return history_.size(); }
  /// Every region's branches proportional to its effective tensor with shared beta_i, e_i,
  /// gamma_i (relative tolerance 1e-10), or no branches at all.
  bool separable() const { return separable_; }
  /// Advanced in contact space: separable() and not parameters.cell_dissipation.
  bool contact_space() const { return contact_space_; }

  /// Energy dissipated by the branches' dashpots since rest (J): sum over steps, quadrature
  /// points and branches of int_{t_n}^{t_n+1} h_i : C_i^-1 : h_i / tau_i dt, integrated in closed
  /// form for the strain linear in time over the step (the assumption under which the recursive
  /// update is exact). Accumulated by advance() without allocation.
  double dissipated_energy() const { return dissipated_energy_; }
  /// Energy dissipated per active cell since rest (J), indexed by active_cell_index(); empty
  /// in the contact-space form.
  const std::vector<double>& cell_dissipated_energy() const { return cell_dissipation_; }
  /// Work of the contact forces on the sole since rest (J): sum over steps of the trapezoid
  /// (f^n + f^{n+1}) / 2 . (u_c^{n+1} - u_c^n) (forces and displacements of advance()).
  double external_work() const { return external_work_; }
  /// Free energy stored at t_n (J): int 1/2 eps : C_inf : eps + sum_i 1/2 h_i : C_i^-1 : h_i
  /// (every cell, elastic regions included). Loops over the cells; allocates nothing.
  double stored_energy() const;
  /// The cell fields at t_n (dissipated energy density, von Mises, overstress norms; the
  /// density empty in the contact-space form). Allocates (output steps only).
  ViscoelasticCellFields cell_fields() const;

  /// Volume average of the strain at t_n (homogeneous-strain tests).
  dealii::SymmetricTensor<2, 3> mean_strain() const;

private:
  struct Impl; // UMFPACK LU of K_eff, FEValues and the step's workspace
  // Per material id: the step's constants.
  struct RegionStep {
    dealii::SymmetricTensor<4, 3> effective;        // C_eff, Pa
    dealii::SymmetricTensor<4, 3> long_term;        // C_inf, Pa
    std::vector<double> shear, bulk, decay, gamma;  // G_i, K_i (Pa), e_i, gamma_i per branch
    double effective_shear = 0, effective_bulk = 0; // G_eff, K_eff = G_inf + sum gamma_i G_i, ...
    // Dissipation over one step of h(s) = a E + c (tau/dt)(1 - E), E = exp(-s/tau), a = h^n,
    // c = C_i : (eps^{n+1} - eps^n): int h : C^-1 : h / tau ds = w_aa m(a,a) + w_ac m(a,c) +
    // w_cc m(c,c), m(x,y) = x : C_i^-1 : y (dimensionless weights, s/tau integrated).
    std::vector<double> w_aa, w_ac, w_cc;
  };
  /// x : C_i^-1 : y for branch moduli G_i, K_i (a zero modulus: its part of h is zero).
  static double inverse_product(const dealii::SymmetricTensor<2, 3>& x,
                                const dealii::SymmetricTensor<2, 3>& y, double shear, double bulk);
  /// Strain at quadrature point @p q of active cell @p index from the cell's dof values
  /// @p local; uses the stored geometry (no allocation).
  dealii::SymmetricTensor<2, 3> strain_at(unsigned int index, unsigned int q,
                                          const double* local) const;

  void assemble_effective_stiffness();
  void store_geometry();
  void update_history();
  // separable_ and the shared branch constants from regions_.
  void check_separable();
  // advance() in contact space.
  void advance_contact_space(const dealii::Vector<double>& contact_forces,
                             const dealii::Vector<double>* contact_displacement);
  // @p field = K_eff^-1 P @p force (n_dofs; @p force 3 n_c, contact space).
  void field_of_contact_forces(const dealii::Vector<double>& force,
                               dealii::Vector<double>& field) const;

  const dealii::Triangulation<3>& triangulation_;
  const Discretization& discretization_;
  const ViscoelasticMaterialTable& materials_;
  ViscoelasticCondensationParameters parameters_;
  dealii::DoFHandler<3> dof_handler_;
  dealii::AffineConstraints<double> constraints_;
  std::unique_ptr<Impl> impl_;

  std::map<dealii::types::material_id, RegionStep> regions_;
  std::vector<const RegionStep*> cell_region_;         // by active cell index
  std::vector<std::size_t> cell_history_;              // first h of each active cell in history_
  std::vector<dealii::SymmetricTensor<2, 3>> history_; // h_i per (cell, q, branch), Pa
  std::vector<dealii::SymmetricTensor<2, 3>> strain_;  // eps^n per (cell, q)

  std::vector<std::array<dealii::types::global_dof_index, 3>> contact_dofs_;
  std::vector<dealii::Point<3>> contact_positions_;
  std::vector<double> compliance_;
  double raw_asymmetry_ = 0;

  mutable dealii::Vector<double> solution_;
  dealii::Vector<double> rhs_, history_force_, history_solution_;
  dealii::Vector<double> history_displacement_, contact_displacement_;
  dealii::Vector<double> previous_forces_; // f^n (3 n_c), for the work's trapezoid
  std::vector<double> cell_dissipation_;   // J per active cell
  double dissipated_energy_ = 0, external_work_ = 0;
  double time_ = 0;

  // The contact-space form: beta_i and the shared step constants per branch; a, b_i, q_c,i
  // (3 n_c each; contact_displacement_ is u_c); solution_ current or not.
  bool separable_ = false, contact_space_ = false;
  std::vector<double> beta_, decay_, gamma_, w_aa_, w_ac_, w_cc_;
  dealii::Vector<double> force_state_, next_force_state_, next_contact_displacement_;
  std::vector<dealii::Vector<double>> branch_force_state_, branch_contact_history_;
  mutable bool solution_current_ = true;
  ViscoelasticTimings timings_;
};

} // namespace plantar::fem
