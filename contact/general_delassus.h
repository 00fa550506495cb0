#pragma once
// A general Delassus operator W (3n x 3n) given as a matrix, dense or sparse, for problems that
// do not come as G G^T + compliant blocks (e.g. third-party problems (W, q, mu), Siconos's
// FrictionContactProblem). ContactProblem::general holds one; the problem's W is then
//   W = general + G G^T + blockdiag(compliant patches)
// (a third-party problem has rigid rank 0 and no patches).
//
// W need not be symmetric: a relative asymmetry max|W - W^T| / max|W| up to a limit (default
// 1e-3) is accepted and reported, a larger one refused. With AsymmetryPolicy::keep the solvers
// use W as given (Gauss-Seidel, Newton exactly; ADMM factorises the symmetric part and takes
// the skew part explicitly), so they solve the problem that was posed; with ::symmetrise W is
// replaced by (W + W^T) / 2 (a different problem, off by the asymmetry).
//
// Storage is row-major (the rows of one contact are contiguous), so that a contact's velocity
// W_k: p costs one pass over its three rows.

#include <Eigen/Core>
#include <Eigen/SparseCore>

namespace plantar::contact {

enum class AsymmetryPolicy {
  keep,       ///< solve with W as given (the posed problem)
  symmetrise, ///< replace W by (W + W^T) / 2
};

class GeneralDelassus {
public:
  enum class Storage { none, dense, sparse };
  using DenseMatrix = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;
  using SparseMatrix = Eigen::SparseMatrix<double, Eigen::RowMajor>;

  /// Sets W (square, 3n x 3n, m/(N s) per N s, i.e. velocity per impulse), dense. Returns its
  /// relative asymmetry max_ij |W_ij - W_ji| / max_ij |W_ij|. Throws std::invalid_argument if W
  /// is not square of a size multiple of 3, has non-finite entries, or its asymmetry exceeds
  /// @p asymmetry_limit (the message names both). Allocates (set-up, not in the time loop).
  double set_dense(const Eigen::Ref<const Eigen::MatrixXd>& w,
                   AsymmetryPolicy policy = AsymmetryPolicy::keep, double asymmetry_limit = 1e-3);
  /// Same for a sparse W (any storage order; e.g. Siconos's sparse-block matrices).
  double set_sparse(const Eigen::SparseMatrix<double>& w,
                    AsymmetryPolicy policy = AsymmetryPolicy::keep, double asymmetry_limit = 1e-3);
  /// Back to no general part.
  void clear();

  Storage storage() const { return storage_; }
  bool empty() const { return storage_ == Storage::none; }
  /// Rows (= columns) of W: 3n, or 0 when empty.
  int size() const { return size_; }
  /// Relative asymmetry of W as given to the last set_*() call (before any symmetrisation).
  double asymmetry() const { return asymmetry_; }
  /// Stored entries: size()^2 (dense) or the sparse non-zeros.
  long nonzeros() const {
    return storage_ == Storage::sparse ? static_cast<long>(sparse_.nonZeros())
                                       : static_cast<long>(size_) * size_;
  }
  /// W_ij == W_ji for all ij (as stored).
  bool symmetric() const { return stored_asymmetry_ == 0.0; }

  /// out (3n) += W p (3n). Does not allocate.
  void add_product(const Eigen::Ref<const Eigen::VectorXd>& p,
                   Eigen::Ref<Eigen::VectorXd> out) const;
  /// out (3n) += (W - W^T) p / 2: the skew part's product. Does not allocate.
  void add_skew_product(const Eigen::Ref<const Eigen::VectorXd>& p,
                        Eigen::Ref<Eigen::VectorXd> out) const;
  /// Rows 3k..3k+2 of W times @p p (3n): contact k's velocity from all impulses. O(row entries).
  Eigen::Vector3d contact_rows_times(int contact, const double* p) const;
  /// W_kk (3x3).
  Eigen::Matrix3d diagonal_block(int contact) const;
  /// out (3n x 3n) += W, or += (W + W^T)/2 when @p symmetric_part. Does not allocate.
  void add_to_dense(Eigen::Ref<Eigen::MatrixXd> out, bool symmetric_part) const;

  const DenseMatrix& dense() const { return dense_; }
  const SparseMatrix& sparse() const { return sparse_; }

private:
  Storage storage_ = Storage::none;
  int size_ = 0;
  double asymmetry_ = 0.0;
  double stored_asymmetry_ = 0.0;
  DenseMatrix dense_;
  SparseMatrix sparse_;
};

} // namespace plantar::contact
