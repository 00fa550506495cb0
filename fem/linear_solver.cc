#include "fem/linear_solver.h"

#include <deal.II/lac/petsc_precondition.h>
#include <deal.II/lac/petsc_solver.h>
#include <deal.II/lac/petsc_sparse_matrix.h>
#include <deal.II/lac/petsc_vector.h>
#include <deal.II/lac/solver_control.h>

#include <petscsys.h>

#include <cstdlib>
#include <sstream>
#include <stdexcept>

namespace plantar::fem {
namespace {

// PETSc (and MPI) are started on first use, so that programs and tests that
// never take the iterative path need no MPI set-up.
void ensure_petsc_initialized() {
  PetscBool initialized = PETSC_FALSE;
  PetscInitialized(&initialized);
  if (!initialized) {
    if (PetscInitializeNoArguments() != 0)
      throw std::runtime_error("PETSc could not be initialized");
    std::atexit([] { PetscFinalize(); });
  }
}

} // namespace

LinearSolverSettings::Kind LinearSolverSettings::parse_kind(const std::string& text) {
  if (text == "direct")
    return Kind::direct;
  if (text == "iterative")
    return Kind::iterative;
  throw std::invalid_argument("linear solver '" + text +
                              "' is not known (allowed: direct, iterative)");
}

struct LinearSolver::PetscState {
  dealii::PETScWrappers::SparseMatrix matrix;
  dealii::PETScWrappers::PreconditionBoomerAMG preconditioner;
};

LinearSolver::LinearSolver(const LinearSolverSettings& settings) : settings_(settings) {}
LinearSolver::~LinearSolver() = default;

void LinearSolver::initialize(const dealii::SparseMatrix<double>& matrix) {
  matrix_ = &matrix;
  if (settings_.kind == LinearSolverSettings::Kind::direct) {
    direct_.initialize(matrix);
    return;
  }
  ensure_petsc_initialized();
  petsc_ = std::make_unique<PetscState>();
  const auto& sparsity = matrix.get_sparsity_pattern();
  petsc_->matrix.reinit(sparsity);
  for (unsigned int row = 0; row < matrix.m(); ++row)
    for (auto entry = matrix.begin(row); entry != matrix.end(row); ++entry)
      petsc_->matrix.set(row, entry->column(), entry->value());
  petsc_->matrix.compress(dealii::VectorOperation::insert);
  dealii::PETScWrappers::PreconditionBoomerAMG::AdditionalData amg_data;
  amg_data.symmetric_operator = true;
  amg_data.strong_threshold = 0.5; // recommended for 3D problems
  petsc_->preconditioner.initialize(petsc_->matrix, amg_data);
}

void LinearSolver::solve(const dealii::Vector<double>& rhs,
                         dealii::Vector<double>& solution) const {
  if (matrix_ == nullptr)
    throw std::logic_error("LinearSolver::solve called before initialize");
  solution.reinit(rhs.size());
  if (settings_.kind == LinearSolverSettings::Kind::direct) {
    direct_.vmult(solution, rhs);
    last_iterations_ = 0;
    return;
  }
  const dealii::IndexSet all = dealii::complete_index_set(rhs.size());
  dealii::PETScWrappers::MPI::Vector x(all, MPI_COMM_SELF), b(all, MPI_COMM_SELF);
  for (unsigned int i = 0; i < rhs.size(); ++i)
    b[i] = rhs[i];
  b.compress(dealii::VectorOperation::insert);
  dealii::SolverControl control(settings_.max_iterations,
                                settings_.relative_tolerance * rhs.l2_norm());
  dealii::PETScWrappers::SolverCG cg(control, MPI_COMM_SELF);
  try {
    cg.solve(petsc_->matrix, x, b, petsc_->preconditioner);
  } catch (const std::exception&) {
    std::ostringstream msg;
    msg << "iterative linear solver (PETSc CG + BoomerAMG) did not converge: "
        << control.last_step() << " iterations, residual " << control.last_value()
        << " > tolerance " << control.tolerance();
    throw std::runtime_error(msg.str());
  }
  last_iterations_ = control.last_step();
  for (unsigned int i = 0; i < rhs.size(); ++i)
    solution[i] = x[i];
}

} // namespace plantar::fem
