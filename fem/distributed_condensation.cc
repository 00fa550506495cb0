#include "fem/distributed_condensation.h"

#include <deal.II/base/mpi.h>

#include <petscmat.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <numeric>
#include <sstream>
#include <stdexcept>
#include <string>
#include <tuple>

namespace plantar::fem {

using dealii::types::global_dof_index;

namespace {

double seconds_since(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

void check_petsc(PetscErrorCode code, const char* what) {
  if (code != 0)
    throw std::runtime_error(std::string("distributed condensation: PETSc error ") +
                             std::to_string(code) + " in " + what);
}

/// Destroys a PETSc matrix at scope exit.
struct MatGuard {
  Mat mat = nullptr;
  ~MatGuard() {
    if (mat != nullptr)
      MatDestroy(&mat);
  }
};

std::tuple<long long, long long, long long> position_key(const dealii::Point<3>& p) {
  return {std::llround(p[0] * 1e9), std::llround(p[1] * 1e9), std::llround(p[2] * 1e9)};
}

} // namespace

void DistributedCondensationSettings::validate() const {
  if (block_size < 1 || block_size > 4096) {
    std::ostringstream msg;
    msg << "distributed condensation: block size = " << block_size
        << " is out of range: must be in [1, 4096]";
    throw std::invalid_argument(msg.str());
  }
}

DistributedCondensation::DistributedCondensation(const DistributedContact& problem,
                                                 const DistributedCondensationSettings& settings)
    : communicator_(problem.communicator()) {
  settings.validate();
  const Mat stiffness = problem.stiffness_matrix();
  PetscInt first_owned = 0, end_owned = 0, n_dofs = 0;
  check_petsc(MatGetOwnershipRange(stiffness, &first_owned, &end_owned), "MatGetOwnershipRange");
  check_petsc(MatGetSize(stiffness, &n_dofs, nullptr), "MatGetSize");
  const PetscInt n_owned = end_owned - first_owned;

  // The global order of the contact nodes: by position, gathered from their owners.
  std::vector<double> local;
  for (const auto& node : problem.owned_contact_nodes())
    for (unsigned int d = 0; d < 3; ++d) {
      local.push_back(node.position[d]);
      local.push_back(static_cast<double>(node.dofs[d])); // exact below 2^53
    }
  struct GlobalNode {
    dealii::Point<3> position;
    std::array<global_dof_index, 3> dofs;
  };
  std::vector<GlobalNode> nodes;
  for (const auto& part : dealii::Utilities::MPI::all_gather(communicator_, local))
    for (std::size_t i = 0; i + 6 <= part.size(); i += 6) {
      GlobalNode node;
      for (unsigned int d = 0; d < 3; ++d) {
        node.position[d] = part[i + 2 * d];
        node.dofs[d] = static_cast<global_dof_index>(part[i + 2 * d + 1]);
      }
      nodes.push_back(node);
    }
  std::sort(nodes.begin(), nodes.end(), [](const GlobalNode& a, const GlobalNode& b) {
    return position_key(a.position) < position_key(b.position);
  });
  const std::size_t n = 3 * nodes.size();
  std::vector<global_dof_index> column_dof(n);
  positions_.resize(nodes.size());
  for (std::size_t k = 0; k < nodes.size(); ++k) {
    positions_[k] = nodes[k].position;
    for (unsigned int d = 0; d < 3; ++d) {
      column_dof[3 * k + d] = nodes[k].dofs[d];
      const auto dof = static_cast<PetscInt>(nodes[k].dofs[d]);
      if (dof >= first_owned && dof < end_owned)
        local_rows_.push_back(static_cast<unsigned int>(3 * k + d));
    }
  }
  local_compliance_.assign(local_rows_.size() * n, 0.0);

  // K_D: K with the attached dofs' rows and columns replaced by the identity.
  const auto start = std::chrono::steady_clock::now();
  MatGuard k_d, factor;
  check_petsc(MatDuplicate(stiffness, MAT_COPY_VALUES, &k_d.mat), "MatDuplicate");
  std::vector<PetscInt> attached;
  for (const auto& node : problem.owned_attached_nodes())
    for (const global_dof_index dof : node.dofs)
      attached.push_back(static_cast<PetscInt>(dof));
  check_petsc(MatZeroRowsColumns(k_d.mat, static_cast<PetscInt>(attached.size()), attached.data(),
                                 1.0, nullptr, nullptr),
              "MatZeroRowsColumns");
  check_petsc(MatSetOption(k_d.mat, MAT_SPD, PETSC_TRUE), "MatSetOption(MAT_SPD)");
  check_petsc(MatGetFactor(k_d.mat, MATSOLVERMUMPS, MAT_FACTOR_CHOLESKY, &factor.mat),
              "MatGetFactor(MUMPS, Cholesky)");
  MatFactorInfo info;
  check_petsc(MatFactorInfoInitialize(&info), "MatFactorInfoInitialize");
  const auto fail_factor = [&](const char* stage) {
    PetscInt infog1 = 0;
    MatMumpsGetInfog(factor.mat, 1, &infog1);
    std::ostringstream msg;
    msg << "distributed condensation: the MUMPS Cholesky factorisation of K (" << n_dofs
        << " dofs, attached dofs fixed) failed in " << stage << " (INFOG(1) = " << infog1
        << "): is the attached boundary empty or a material parameter out of range?";
    throw std::runtime_error(msg.str());
  };
  if (MatCholeskyFactorSymbolic(factor.mat, k_d.mat, nullptr, &info) != 0)
    fail_factor("the analysis");
  if (MatCholeskyFactorNumeric(factor.mat, k_d.mat, &info) != 0)
    fail_factor("the factorisation");
  MatFactorError error = MAT_FACTOR_NOERROR;
  check_petsc(MatFactorGetError(factor.mat, &error), "MatFactorGetError");
  if (error != MAT_FACTOR_NOERROR)
    fail_factor("the factorisation");
  PetscInt value = 0;
  check_petsc(MatMumpsGetInfog(factor.mat, 22, &value), "MatMumpsGetInfog(22)");
  factor_mb_total_ = static_cast<double>(value);
  check_petsc(MatMumpsGetInfo(factor.mat, 16, &value), "MatMumpsGetInfo(16)");
  factor_mb_rank_ = static_cast<double>(value);
  timings_.factorization = seconds_since(start);

  // Blocks of unit right-hand sides on the contact dofs; each rank keeps its rows of X.
  const auto solve_start = std::chrono::steady_clock::now();
  std::vector<std::size_t> local_offset(local_rows_.size()); // row of X on this rank
  for (std::size_t r = 0; r < local_rows_.size(); ++r)
    local_offset[r] =
        static_cast<std::size_t>(static_cast<PetscInt>(column_dof[local_rows_[r]]) - first_owned);
  const std::size_t block_size =
      std::max<std::size_t>(1, std::min<std::size_t>(settings.block_size, n));
  for (std::size_t first = 0; first < n; first += block_size) {
    const auto count = static_cast<PetscInt>(std::min(block_size, n - first));
    MatGuard rhs, solution;
    check_petsc(
        MatCreateDense(communicator_, n_owned, PETSC_DECIDE, n_dofs, count, nullptr, &rhs.mat),
        "MatCreateDense");
    check_petsc(
        MatCreateDense(communicator_, n_owned, PETSC_DECIDE, n_dofs, count, nullptr, &solution.mat),
        "MatCreateDense");
    for (PetscInt j = 0; j < count; ++j) {
      const auto dof = static_cast<PetscInt>(column_dof[first + j]);
      if (dof >= first_owned && dof < end_owned)
        check_petsc(MatSetValue(rhs.mat, dof, j, 1.0, INSERT_VALUES), "MatSetValue");
    }
    check_petsc(MatAssemblyBegin(rhs.mat, MAT_FINAL_ASSEMBLY), "MatAssemblyBegin");
    check_petsc(MatAssemblyEnd(rhs.mat, MAT_FINAL_ASSEMBLY), "MatAssemblyEnd");
    check_petsc(MatAssemblyBegin(solution.mat, MAT_FINAL_ASSEMBLY), "MatAssemblyBegin");
    check_petsc(MatAssemblyEnd(solution.mat, MAT_FINAL_ASSEMBLY), "MatAssemblyEnd");
    check_petsc(MatMatSolve(factor.mat, rhs.mat, solution.mat), "MatMatSolve");
    const PetscScalar* x = nullptr;
    PetscInt lda = 0;
    check_petsc(MatDenseGetLDA(solution.mat, &lda), "MatDenseGetLDA");
    check_petsc(MatDenseGetArrayRead(solution.mat, &x), "MatDenseGetArrayRead");
    for (std::size_t r = 0; r < local_rows_.size(); ++r)
      for (PetscInt j = 0; j < count; ++j)
        local_compliance_[r * n + first + j] =
            x[local_offset[r] + static_cast<std::size_t>(j) * static_cast<std::size_t>(lda)];
    check_petsc(MatDenseRestoreArrayRead(solution.mat, &x), "MatDenseRestoreArrayRead");
  }
  timings_.contact_solves = seconds_since(solve_start);

  double largest = 0;
  bool finite = true;
  for (const double c : local_compliance_) {
    finite = finite && std::isfinite(c);
    largest = std::max(largest, std::abs(c));
  }
  if (dealii::Utilities::MPI::min(finite ? 1 : 0, communicator_) == 0)
    throw std::runtime_error("distributed condensation: the contact compliance C has non-finite "
                             "entries");
  if (n > 0 && !(dealii::Utilities::MPI::max(largest, communicator_) > 0))
    throw std::runtime_error("distributed condensation: the contact compliance C is zero");
}

std::vector<double> DistributedCondensation::gather(unsigned int root) const {
  const std::size_t n = 3 * positions_.size();
  const auto rows = dealii::Utilities::MPI::gather(communicator_, local_rows_, root);
  const int n_ranks = static_cast<int>(dealii::Utilities::MPI::n_mpi_processes(communicator_));
  const bool is_root = dealii::Utilities::MPI::this_mpi_process(communicator_) == root;
  std::vector<double> received;
  std::vector<int> counts(n_ranks, 0), displacements(n_ranks, 0);
  if (is_root) {
    for (int p = 0; p < n_ranks; ++p)
      counts[p] = static_cast<int>(rows[p].size() * n);
    std::partial_sum(counts.begin(), counts.end() - 1, displacements.begin() + 1);
    received.resize(n * n);
  }
  // Rows of 3 n_c doubles: at most 8 (3 n_c)^2 bytes per message, below 2^31 doubles while
  // 3 n_c < 46340 (the largest C one rank can hold anyway).
  if (n * n >= (std::size_t{1} << 31))
    throw std::runtime_error(
        "distributed condensation: C too large to gather on one rank (3 n_c = " +
        std::to_string(n) + ")");
  MPI_Gatherv(local_compliance_.data(), static_cast<int>(local_compliance_.size()), MPI_DOUBLE,
              received.data(), counts.data(), displacements.data(), MPI_DOUBLE,
              static_cast<int>(root), communicator_);
  if (!is_root)
    return {};
  std::vector<double> compliance(n * n);
  std::size_t offset = 0;
  for (int p = 0; p < n_ranks; ++p)
    for (const unsigned int row : rows[p]) {
      std::copy_n(received.data() + offset, n, compliance.data() + std::size_t{row} * n);
      offset += n;
    }
  return compliance;
}

} // namespace plantar::fem
