#pragma once
// Static linear elasticity of a sole (David et al. 2008, II-B-1: K U = F).
//
//   find u in V (u = g on Gamma_D):  a(u, v) = l(v) for all v in V_0,
//   a(u, v) = int_Omega eps(v) : C(x) : eps(u) dx,   C per material region,
//   l(v)    = int_Omega f . v dx + int_Gamma_N t . v ds + sum F_i v_i.
//
// Dirichlet rows are eliminated with deal.II's AffineConstraints (symmetric,
// the constrained rows keep a positive diagonal), so K is SPD and its inverse
// restricted to free dofs is the sole's compliance.

#include "fem/discretization.h"
#include "fem/linear_solver.h"
#include "fem/material_table.h"

#include <deal.II/base/function.h>
#include <deal.II/base/tensor.h>
#include <deal.II/dofs/dof_handler.h>
#include <deal.II/lac/affine_constraints.h>
#include <deal.II/lac/sparse_matrix.h>
#include <deal.II/lac/sparsity_pattern.h>
#include <deal.II/lac/vector.h>

#include <array>
#include <map>
#include <memory>
#include <vector>

namespace plantar::fem {

class LinearElasticity {
public:
  /// Objects referenced must outlive this one.
  LinearElasticity(const dealii::Triangulation<3>& triangulation,
                   const Discretization& discretization, const MaterialTable& materials);

  /// Distributes dofs and imposes u = g on each boundary id of @p dirichlet
  /// (g a 3-component function in m; nullptr means g = 0).
  void setup(const std::map<dealii::types::boundary_id, const dealii::Function<3>*>& dirichlet);

  /// Assembles K (N/m) and the load of the body force @p body_force (N/m^3,
  /// 3 components; nullptr: none). Resets the load vector.
  void assemble(const dealii::Function<3>* body_force = nullptr);

  /// Adds int_Gamma t . v ds for the uniform traction @p traction (Pa) on the
  /// faces with boundary id @p boundary.
  void add_traction(dealii::types::boundary_id boundary, const dealii::Tensor<1, 3>& traction);
  /// Same for a space-dependent traction (3 components, Pa).
  void add_traction(dealii::types::boundary_id boundary, const dealii::Function<3>& traction);

  /// Factorizes K (direct) or builds the preconditioner (iterative).
  void factorize(const LinearSolverSettings& settings);
  /// Solves K u = F for the current load; factorizes first if needed.
  void solve(const LinearSolverSettings& settings = {});
  /// Solves K x = b with the current factorization; constrained entries of
  /// x are set from the constraints' homogeneous part (zero).
  void solve(const dealii::Vector<double>& rhs, dealii::Vector<double>& x) const;

  const dealii::DoFHandler<3>& dof_handler() const { return dof_handler_; }
  const dealii::AffineConstraints<double>& constraints() const { return constraints_; }
  const dealii::SparseMatrix<double>& stiffness_matrix() const { return stiffness_; }
  const Discretization& discretization() const { return discretization_; }
  const MaterialTable& materials() const { return materials_; }
  dealii::Vector<double>& load() { return load_; } ///< F, N
  const dealii::Vector<double>& load() const { return load_; }
  const dealii::Vector<double>& solution() const { return solution_; } ///< u, m
  dealii::Vector<double>& solution() { return solution_; }
  const LinearSolver& solver() const;

  /// Support point (m) of every dof, in the mesh frame (size n_dofs).
  std::vector<dealii::Point<3>> support_points() const;
  /// Dofs on the faces with boundary id @p boundary, grouped per node:
  /// entry k holds the x, y, z dofs of node k (sorted by dof index).
  std::vector<std::array<dealii::types::global_dof_index, 3>>
  boundary_nodes(dealii::types::boundary_id boundary) const;
  /// max over support points of |u| (m).
  double max_displacement() const;
  /// Sum of the reaction forces (N) on the dofs of boundary @p boundary:
  /// (K u - F) summed per component (uses the unconstrained element matrices).
  dealii::Tensor<1, 3> reaction_force(dealii::types::boundary_id boundary) const;
  /// ||u - u_exact||_L2 (m * m^1.5) and |u - u_exact|_H1 (m^1.5) with an
  /// over-integrating quadrature.
  std::pair<double, double> errors(const dealii::Function<3>& exact) const;
  /// Volume average of the strain and of the Cauchy stress (Pa).
  std::pair<dealii::SymmetricTensor<2, 3>, dealii::SymmetricTensor<2, 3>>
  mean_strain_stress() const;

private:
  const dealii::Triangulation<3>& triangulation_;
  const Discretization& discretization_;
  const MaterialTable& materials_;
  dealii::DoFHandler<3> dof_handler_;
  dealii::AffineConstraints<double> constraints_;
  dealii::SparsityPattern sparsity_;
  dealii::SparseMatrix<double> stiffness_;
  dealii::Vector<double> load_, solution_;
  dealii::Vector<double> external_load_; // body force and tractions, unconstrained
  std::unique_ptr<LinearSolver> solver_;
};

} // namespace plantar::fem
