#pragma once
// Solvers for the sole's symmetric positive definite stiffness system K u = f:
// a sparse direct factorization (UMFPACK), kept for many right-hand sides, or
// PETSc conjugate gradients with an algebraic multigrid (hypre BoomerAMG)
// preconditioner for large meshes.

#include <deal.II/lac/sparse_direct.h>
#include <deal.II/lac/sparse_matrix.h>
#include <deal.II/lac/vector.h>

#include <memory>
#include <string>

namespace plantar::fem {

struct LinearSolverSettings {
  enum class Kind { direct, iterative };
  Kind kind = Kind::direct;
  double relative_tolerance = 1e-10; ///< iterative: ||r|| <= tol ||f||
  unsigned int max_iterations = 10000;

  /// "direct" or "iterative"; throws std::invalid_argument otherwise.
  static Kind parse_kind(const std::string& text);
};

class LinearSolver {
public:
  explicit LinearSolver(const LinearSolverSettings& settings);
  ~LinearSolver();

  /// Prepares for solves with @p matrix (factorizes it for the direct solver).
  /// The matrix must outlive the solver.
  void initialize(const dealii::SparseMatrix<double>& matrix);
  /// Solves K x = b. Throws std::runtime_error with the iteration count and
  /// residual if the iterative solver does not converge.
  void solve(const dealii::Vector<double>& rhs, dealii::Vector<double>& solution) const;

  unsigned int last_iterations() const { return last_iterations_; }

private:
  struct PetscState;
  LinearSolverSettings settings_;
  const dealii::SparseMatrix<double>* matrix_ = nullptr;
  dealii::SparseDirectUMFPACK direct_;
  std::unique_ptr<PetscState> petsc_;
  mutable unsigned int last_iterations_ = 0;
};

} // namespace plantar::fem
