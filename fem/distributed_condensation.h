#pragma once
// The contact compliance of a sole built on several ranks (issue 26): the operator of
// coupling::CondensedSole (fem/contact_condensation.h) on the distributed PETSc system of a
// fem::DistributedContact, for soles whose factor does not fit one rank's memory.
//
// The attached (top) nodes are fixed, u = 0; the contact (bottom) nodes carry the load, the
// other dofs none. With K_D the stiffness K with the attached dofs' rows and columns replaced by
// the identity,
//
//   C = [K_D^-1]_cc = (K_cc - K_cn K_nn^-1 K_nc)^-1     (3 n_c x 3 n_c, m/N),
//
// computed as K_D X = E: one sparse Cholesky factorisation of K_D (MUMPS through PETSc,
// distributed over the ranks), then blocks of unit right-hand sides E on the contact dofs
// (MatMatSolve, block_size columns at a time). Each rank keeps the rows of C of the contact
// nodes whose dofs it owns (its rows of X: no communication); gather() assembles C on demand.
//
// Ordering: contact node k is the k-th by position (x, then y, then z, rounded to 1e-9 m), the
// order of DistributedContact::gather_contact_nodes(), whatever the partition; row and column
// 3k + d is component d (sole frame x, y, z) of node k. C is not symmetrised (its asymmetry is
// round-off: relative_asymmetry of the gathered C). The factor is released after construction.

#include "fem/distributed_contact.h"

#include <deal.II/base/point.h>

#include <mpi.h>

#include <cstddef>
#include <vector>

namespace plantar::fem {

struct DistributedCondensationSettings {
  unsigned int block_size = 128; ///< right-hand sides per MatMatSolve, [1, 4096]
  /// Throws std::invalid_argument naming the field, its value and the allowed range.
  void validate() const;
};

/// Wall-clock seconds of each stage (this rank).
struct DistributedCondensationTimings {
  double factorization = 0;  ///< MUMPS analysis and Cholesky factorisation of K_D
  double contact_solves = 0; ///< the 3 n_c solves K_D x = e_j, in blocks
  double total() const { return factorization + contact_solves; }
};

class DistributedCondensation {
public:
  /// Condenses the sole of @p problem (its mesh, K and boundaries; only read) onto its contact
  /// nodes (see above). Collective over problem.communicator().
  /// @throws std::invalid_argument for bad @p settings;
  /// @throws std::runtime_error if MUMPS fails (K_D not positive definite: nothing attached)
  ///   or C has a non-finite entry or is zero.
  DistributedCondensation(const DistributedContact& problem,
                          const DistributedCondensationSettings& settings = {});

  unsigned int n_contact_nodes() const { return static_cast<unsigned int>(positions_.size()); }
  /// Unloaded positions of the contact nodes in the global order (m), on every rank.
  const std::vector<dealii::Point<3>>& contact_positions() const { return positions_; }
  /// Global indices (3k + d) of this rank's rows of C, ascending.
  const std::vector<unsigned int>& local_rows() const { return local_rows_; }
  /// This rank's rows of C, row-major (local_rows().size() x 3 n_c), m/N.
  const std::vector<double>& local_compliance() const { return local_compliance_; }
  /// C (3 n_c x 3 n_c, row-major, m/N) on @p root, empty on the other ranks. Collective;
  /// allocates 16 (3 n_c)^2 bytes on @p root (received, then reordered).
  std::vector<double> gather(unsigned int root = 0) const;

  const DistributedCondensationTimings& timings() const { return timings_; }
  /// MUMPS's factor memory (INFOG(22): MB, all ranks; INFO(16): MB, this rank) at the peak.
  double factor_megabytes_total() const { return factor_mb_total_; }
  double factor_megabytes_rank() const { return factor_mb_rank_; }

private:
  MPI_Comm communicator_;
  std::vector<dealii::Point<3>> positions_;
  std::vector<unsigned int> local_rows_;
  std::vector<double> local_compliance_;
  DistributedCondensationTimings timings_;
  double factor_mb_total_ = 0, factor_mb_rank_ = 0;
};

} // namespace plantar::fem
