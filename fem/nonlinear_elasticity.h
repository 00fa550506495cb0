#pragma once
// Static finite-strain elasticity of a sole, total Lagrangian (deal.II
// step-44 structure): find u with u = lambda g on Gamma_D and
//   R(u) = int_Omega P(F) : grad_X v dX - lambda (int_Gamma_N T . v dA + F_nodal . v) = 0,
// F = I + grad_X u, P from the region's HyperelasticLaw, dead loads in the
// reference configuration scaled by the load factor lambda. Newton-Raphson
// with a backtracking line search on ||R||; tangent K = int grad v : A : grad du.
//
// Formulations:
//  - displacement: W(F) = W_iso + U(J) at every quadrature point (locks for
//    nu -> 0.5 with P1/Q1).
//  - mixed: three-field Hu-Washizu with discontinuous pressure p and
//    dilatation J~ of polynomial degree pressure_degree per element
//    (Q2-P1-P1, Q1-P0-P0 as in step-44, P2-P0-P0 on tetrahedra), both
//    condensed per element: J~ = Pi(J), p = Pi(U'(J~)) (Pi = L2 projection on
//    the element), residual int P_iso : grad v + p J F^-T : grad v, tangent
//    K_iso + int p d(J F^-T) + G^T M^-1 M_U'' M^-1 G,
//    G_ai = int phi_a J F^-T : grad N_i, M = int phi phi, M_U'' = int phi U''(J~) phi.
//    The global unknowns are displacements only.
// The linear problem (small strain) is solve_linearized(): one Newton step
// from u = 0, whose tangent is the linear elasticity tensor with the laws'
// small-strain E and nu (mixed: the B-bar form, locking-free).
//
// Visco-hyperelastic regions (materials().has_viscosity(), fem/visco_hyperelastic_law.h): each
// solve is one time step of length time_step() from the committed internal variables (the
// algorithmic stress and tangent); advance() commits them at the converged state. A failed
// solve leaves them untouched (rollback: restore solution() and solve again, e.g. with a
// smaller dt). In the mixed formulation the overstresses act on the isochoric part only.

#include "fem/discretization.h"
#include "fem/hyperelastic_material_table.h"
#include "fem/visco_hyperelastic_history.h"

#include <deal.II/base/function.h>
#include <deal.II/base/tensor.h>
#include <deal.II/dofs/dof_handler.h>
#include <deal.II/lac/affine_constraints.h>
#include <deal.II/lac/sparse_direct.h>
#include <deal.II/lac/sparse_matrix.h>
#include <deal.II/lac/sparsity_pattern.h>
#include <deal.II/lac/vector.h>

#include <array>
#include <optional>
#include <vector>

namespace plantar::fem {

struct NonlinearSettings {
  enum class Formulation { displacement, mixed };
  Formulation formulation = Formulation::displacement;
  /// Mixed only: degree (0 or 1) of the element-wise pressure and dilatation;
  /// -1 = automatic (element degree - 1 on hexahedra, 0 on tetrahedra).
  int pressure_degree = -1;
  /// Converged when ||R|| <= residual_tolerance * max(||R_0||, ||lambda F_ext||), range (0, 1),
  /// or when a Newton update is below round-off, ||du||_inf <= 1e3 eps h_min (a nearly
  /// unloaded sole: the residual's floor is then above the relative tolerance).
  double residual_tolerance = 1e-9;
  unsigned int max_iterations = 30;  ///< Newton iterations per load step, >= 1
  unsigned int max_line_search = 12; ///< step halvings per iteration, >= 0
  /// Throws std::invalid_argument naming the field, its value and the range.
  void validate() const;
};

/// Dirichlet condition u_c = lambda g_c on boundary id @p boundary for the components marked.
struct DirichletCondition {
  dealii::types::boundary_id boundary = 0;
  const dealii::Function<3>* displacement = nullptr; ///< g (m, 3 components); nullptr: 0
  std::array<bool, 3> components{{true, true, true}};
};

/// Outcome of a Newton solve.
struct NewtonReport {
  unsigned int load_steps = 0;
  unsigned int iterations = 0;       ///< total over the load steps
  unsigned int line_search_cuts = 0; ///< total step halvings
  double final_residual = 0;         ///< ||R|| at the end, N
  double min_jacobian = 0;           ///< min over quadrature points of det F
};

class NonlinearElasticity {
public:
  /// Objects referenced must outlive this one. Throws on invalid settings.
  NonlinearElasticity(const dealii::Triangulation<3>& triangulation,
                      const Discretization& discretization,
                      const HyperelasticMaterialTable& materials,
                      const NonlinearSettings& settings = {});

  /// Distributes dofs, sets u = 0, clears the loads and records the Dirichlet conditions.
  void setup(const std::vector<DirichletCondition>& dirichlet);
  /// Adds the dead traction @p traction (Pa, per reference area) on faces with id @p boundary.
  void add_traction(dealii::types::boundary_id boundary, const dealii::Tensor<1, 3>& traction);
  /// External nodal forces (N), dof order; scaled by the load factor with the tractions.
  dealii::Vector<double>& nodal_load() { return nodal_load_; }

  /// Newton solve at load factor @p load_factor from the current state (Dirichlet
  /// values and loads times the factor). Throws std::runtime_error with the
  /// iteration count and residual if Newton does not converge or an element inverts.
  NewtonReport solve_at(double load_factor);
  /// Ramps the load factor from 0 to 1 in @p n_load_steps equal steps (from u = 0).
  NewtonReport solve(unsigned int n_load_steps = 1);
  /// Linear elasticity at full load: K_T(0) u = F with u = g on Gamma_D (the
  /// small-strain solution); afterwards reaction_force() gives the linear
  /// reactions K u - F (K u by a central difference of the internal force
  /// at +-1e-7 u / |u|_inf, exact up to round-off for the linear part).
  void solve_linearized();

  /// Time step dt (s, > 0) of the next solves (visco-hyperelastic regions; ignored otherwise).
  /// Throws std::invalid_argument naming the value and the range.
  void set_time_step(double dt);
  double time_step() const { return time_step_; }
  /// Commits the internal variables at the current state (the converged solution of the last
  /// solve, re-evaluated here): Q_i <- e_i Q_i + beta_i gamma_i (S_iso - S_iso^n). No-op
  /// without viscous regions. Throws as solve_at if an element is inverted.
  void advance();
  /// After advance(): the displacement change (m, dof order, 0 on constrained dofs) that the
  /// relaxation over the next step of time_step() causes at fixed loads, to first order:
  /// -K_T^-1 R(u), R assembled with the committed internal variables, K_T the last factorized
  /// tangent (the last Newton iteration's or factorize_tangent()'s). Zero without viscous
  /// regions. Exact for the linear law.
  void history_drift(dealii::Vector<double>& drift);
  /// Internal variables back to the virgin state (called by setup()).
  void reset_history();
  /// The internal variables (nullptr without viscous regions; valid after setup()).
  const ViscoHyperelasticHistory* history() const { return history_ ? &*history_ : nullptr; }

  /// Assembles the tangent at the current state (Dirichlet rows eliminated)
  /// and factorizes it (UMFPACK); then solve_tangent solves K_T x = b with
  /// x = 0 on constrained dofs.
  void factorize_tangent();
  void solve_tangent(const dealii::Vector<double>& rhs, dealii::Vector<double>& x) const;

  const dealii::DoFHandler<3>& dof_handler() const { return dof_handler_; }
  const dealii::AffineConstraints<double>& constraints() const { return constraints_; }
  const Discretization& discretization() const { return discretization_; }
  const HyperelasticMaterialTable& materials() const { return materials_; }
  const dealii::Vector<double>& solution() const { return solution_; } ///< u, m
  dealii::Vector<double>& solution() { return solution_; }
  double load_factor() const { return load_factor_; }
  int pressure_degree() const { return pressure_degree_; }

  /// Dofs on faces with id @p boundary, per node (x, y, z), sorted by first dof.
  std::vector<std::array<dealii::types::global_dof_index, 3>>
  boundary_nodes(dealii::types::boundary_id boundary) const;
  /// Support point (reference, m) of every dof.
  std::vector<dealii::Point<3>> support_points() const;
  /// Sum over the nodes of @p boundary of the internal forces int P : grad N (N):
  /// the force the body exerts back on whatever holds that boundary, negated.
  dealii::Tensor<1, 3> reaction_force(dealii::types::boundary_id boundary) const;
  /// min over quadrature points of det F at the current state.
  double min_jacobian() const;
  /// max over dof support points of |u| (m).
  double max_displacement() const;
  /// u at the reference point @p point (m); throws if outside the mesh.
  dealii::Tensor<1, 3> displacement_at(const dealii::Point<3>& point) const;

private:
  /// Assembles R (with constraints: zero on constrained dofs) and, if
  /// @p with_tangent, K. Also fills internal_force_ (unconstrained). Throws
  /// std::runtime_error if an element inverts.
  void assemble(bool with_tangent, const dealii::AffineConstraints<double>* predictor = nullptr);
  double residual_norm() const { return residual_.l2_norm(); }
  void apply_dirichlet_values(double load_factor);

  const dealii::Triangulation<3>& triangulation_;
  const Discretization& discretization_;
  const HyperelasticMaterialTable& materials_;
  NonlinearSettings settings_;
  int pressure_degree_ = 0;
  dealii::DoFHandler<3> dof_handler_;
  std::vector<DirichletCondition> dirichlet_;
  dealii::AffineConstraints<double> constraints_;
  dealii::SparsityPattern sparsity_;
  dealii::SparseMatrix<double> tangent_;
  dealii::SparseDirectUMFPACK factorization_;
  dealii::Vector<double> solution_, residual_, newton_rhs_, internal_force_, traction_load_,
      nodal_load_;
  double load_factor_ = 0;
  double min_jacobian_ = 1;
  double round_off_step_ = 0; ///< m: 1e3 eps h_min
  double time_step_ = 0;
  std::optional<ViscoHyperelasticHistory> history_;
};

} // namespace plantar::fem
