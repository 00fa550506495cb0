#pragma once
// The linear system of a semismooth Newton iteration (semismooth_newton_solver.h) for a problem
// given by a block-sparse general W alone (no rigid factor, no patches: third-party problems,
// general_delassus.h), solved by a sparse LU (Eigen's SparseLU, COLAMD ordering) of
//   J_AA + delta I,   block (i, l) = B_i W_il + [i = l] (A_i + delta I),
// over the 3 x 3 blocks of W between active contacts (block pattern of W, diagonal included).
// The symbolic analysis (column ordering, elimination tree) is kept while the active set does
// not change; each factorize() redoes only the numeric factorisation.
//
// Not for the time loop: prepare(), factorize() and solve() allocate (Eigen's SparseLU and the
// pattern, per solve and per active set); the robot's problems never take this path.

#include "contact/contact_problem.h"

#include <Eigen/Core>
#include <Eigen/SparseCore>
#include <Eigen/SparseLU>
#include <vector>

namespace plantar::contact {

class SparseNewtonSystem {
public:
  /// The form it solves: a general W stored sparse, rigid rank 0, no patches.
  static bool applicable(const ContactProblem& problem);
  /// Fraction of the n^2 contact pairs whose 3 x 3 block of W is stored (0 when not applicable).
  static double block_density(const ContactProblem& problem);

  /// The 3 x 3 blocks of W by block columns (allocates). Call once per solve.
  void prepare(const ContactProblem& problem);
  /// Assembles and factorises J_AA + delta I for the active contacts @p active (n_active,
  /// ascending) with the blocks @p a_blocks, @p b_blocks (3 x 3N, contact k at columns 3k),
  /// re-analysing the pattern when the active set changed. Returns false when the sparse LU fails.
  bool factorize(const int* active, int n_active, const Eigen::MatrixXd& a_blocks,
                 const Eigen::MatrixXd& b_blocks, double delta);
  /// x (3 n_active, by active position) <- (J_AA + delta I)^-1 x.
  void solve(Eigen::Ref<Eigen::VectorXd> x);
  /// Symbolic analyses done since prepare() (for tests: one per distinct active set).
  int n_analyses() const { return n_analyses_; }

private:
  struct Entry { // a stored block of J_AA, in column-major order of blocks
    int row_position, row_contact, block;
    bool diagonal;
  };
  int n_ = 0;
  std::vector<int> column_start_;       // n + 1: blocks of W by block column
  std::vector<int> column_row_;         // block row (contact) of each
  std::vector<Eigen::Matrix3d> blocks_; // their values
  std::vector<int> position_;           // n: active position of each contact, or -1
  std::vector<int> pattern_active_;     // the active set of the present pattern
  std::vector<int> entry_start_;        // n_active + 1: entries of each block column
  std::vector<Entry> entries_;
  Eigen::SparseMatrix<double> matrix_;
  Eigen::SparseLU<Eigen::SparseMatrix<double>, Eigen::COLAMDOrdering<int>> lu_;
  Eigen::VectorXd solution_;
  int n_analyses_ = 0;
  bool pattern_valid_ = false;
};

} // namespace plantar::contact
