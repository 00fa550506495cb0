#include "contact/general_delassus.h"

#include "contact/symmetry.h"

#include <cmath>
#include <sstream>
#include <stdexcept>

namespace plantar::contact {

namespace {
void check_shape(Eigen::Index rows, Eigen::Index cols, const char* where) {
  if (rows != cols || rows % 3 != 0) {
    std::ostringstream msg;
    msg << "GeneralDelassus::" << where << ": W is " << rows << "x" << cols
        << ", expected square of size 3 n_contacts";
    throw std::invalid_argument(msg.str());
  }
}

void check_asymmetry(double asymmetry, double limit, const char* where) {
  if (!(asymmetry <= limit)) {
    std::ostringstream msg;
    msg << "GeneralDelassus::" << where << ": W is not symmetric enough: relative asymmetry "
        << "max|W - W^T| / max|W| = " << asymmetry << " > limit " << limit
        << " (the solvers need W close to symmetric positive semi-definite)";
    throw std::invalid_argument(msg.str());
  }
}
} // namespace

double GeneralDelassus::set_dense(const Eigen::Ref<const Eigen::MatrixXd>& w,
                                  AsymmetryPolicy policy, double asymmetry_limit) {
  check_shape(w.rows(), w.cols(), "set_dense");
  if (!w.allFinite())
    throw std::invalid_argument("GeneralDelassus::set_dense: W has non-finite entries");
  const double asymmetry = relative_asymmetry(w);
  check_asymmetry(asymmetry, asymmetry_limit, "set_dense");
  sparse_ = SparseMatrix();
  dense_ = w;
  if (policy == AsymmetryPolicy::symmetrise && asymmetry > 0.0) {
    const DenseMatrix transposed = dense_.transpose();
    dense_ = 0.5 * (dense_ + transposed);
  }
  storage_ = Storage::dense;
  size_ = static_cast<int>(w.rows());
  asymmetry_ = asymmetry;
  stored_asymmetry_ = policy == AsymmetryPolicy::symmetrise ? 0.0 : asymmetry;
  return asymmetry;
}

double GeneralDelassus::set_sparse(const Eigen::SparseMatrix<double>& w, AsymmetryPolicy policy,
                                   double asymmetry_limit) {
  check_shape(w.rows(), w.cols(), "set_sparse");
  double largest = 0.0;
  for (Eigen::Index j = 0; j < w.outerSize(); ++j)
    for (Eigen::SparseMatrix<double>::InnerIterator it(w, j); it; ++it) {
      if (!std::isfinite(it.value()))
        throw std::invalid_argument("GeneralDelassus::set_sparse: W has non-finite entries");
      largest = std::max(largest, std::abs(it.value()));
    }
  const Eigen::SparseMatrix<double> transposed = w.transpose();
  const Eigen::SparseMatrix<double> difference = w - transposed;
  double asymmetry = 0.0;
  for (Eigen::Index j = 0; j < difference.outerSize(); ++j)
    for (Eigen::SparseMatrix<double>::InnerIterator it(difference, j); it; ++it)
      asymmetry = std::max(asymmetry, std::abs(it.value()));
  asymmetry = largest > 0.0 ? asymmetry / largest : 0.0;
  check_asymmetry(asymmetry, asymmetry_limit, "set_sparse");
  dense_ = DenseMatrix();
  if (policy == AsymmetryPolicy::symmetrise && asymmetry > 0.0)
    sparse_ = 0.5 * (w + transposed);
  else
    sparse_ = w;
  sparse_.makeCompressed();
  storage_ = Storage::sparse;
  size_ = static_cast<int>(w.rows());
  asymmetry_ = asymmetry;
  stored_asymmetry_ = policy == AsymmetryPolicy::symmetrise ? 0.0 : asymmetry;
  return asymmetry;
}

void GeneralDelassus::clear() {
  *this = GeneralDelassus();
}

void GeneralDelassus::add_product(const Eigen::Ref<const Eigen::VectorXd>& p,
                                  Eigen::Ref<Eigen::VectorXd> out) const {
  if (storage_ == Storage::dense)
    out.head(size_).noalias() += dense_ * p.head(size_);
  else if (storage_ == Storage::sparse)
    out.head(size_).noalias() += sparse_ * p.head(size_);
}

void GeneralDelassus::add_skew_product(const Eigen::Ref<const Eigen::VectorXd>& p,
                                       Eigen::Ref<Eigen::VectorXd> out) const {
  if (stored_asymmetry_ == 0.0)
    return;
  if (storage_ == Storage::dense) {
    out.head(size_).noalias() += 0.5 * (dense_ * p.head(size_));
    out.head(size_).noalias() -= 0.5 * (dense_.transpose() * p.head(size_));
  } else if (storage_ == Storage::sparse) {
    for (Eigen::Index i = 0; i < sparse_.outerSize(); ++i) // row i of W: W_ij p_j and W^T
      for (SparseMatrix::InnerIterator it(sparse_, i); it; ++it) {
        out[i] += 0.5 * it.value() * p[it.col()];
        out[it.col()] -= 0.5 * it.value() * p[i];
      }
  }
}

Eigen::Vector3d GeneralDelassus::contact_rows_times(int contact, const double* p) const {
  Eigen::Vector3d out = Eigen::Vector3d::Zero();
  const int r = 3 * contact;
  if (storage_ == Storage::dense) {
    const Eigen::Map<const Eigen::VectorXd> x(p, size_);
    out[0] = dense_.row(r).dot(x.transpose());
    out[1] = dense_.row(r + 1).dot(x.transpose());
    out[2] = dense_.row(r + 2).dot(x.transpose());
  } else if (storage_ == Storage::sparse) {
    for (int i = 0; i < 3; ++i) {
      double sum = 0.0;
      for (SparseMatrix::InnerIterator it(sparse_, r + i); it; ++it)
        sum += it.value() * p[it.col()];
      out[i] = sum;
    }
  }
  return out;
}

Eigen::Matrix3d GeneralDelassus::diagonal_block(int contact) const {
  const int r = 3 * contact;
  if (storage_ == Storage::dense)
    return dense_.block<3, 3>(r, r);
  Eigen::Matrix3d block = Eigen::Matrix3d::Zero();
  if (storage_ == Storage::sparse)
    for (int i = 0; i < 3; ++i)
      for (SparseMatrix::InnerIterator it(sparse_, r + i); it; ++it)
        if (it.col() >= r && it.col() < r + 3)
          block(i, it.col() - r) = it.value();
  return block;
}

void GeneralDelassus::add_to_dense(Eigen::Ref<Eigen::MatrixXd> out, bool symmetric_part) const {
  const double half = symmetric_part ? 0.5 : 1.0;
  if (storage_ == Storage::dense) {
    auto block = out.topLeftCorner(size_, size_);
    if (!symmetric_part || stored_asymmetry_ == 0.0) {
      block += dense_;
    } else {
      block += half * dense_;
      block += half * dense_.transpose();
    }
  } else if (storage_ == Storage::sparse) {
    const bool split = symmetric_part && stored_asymmetry_ != 0.0;
    for (Eigen::Index i = 0; i < sparse_.outerSize(); ++i)
      for (SparseMatrix::InnerIterator it(sparse_, i); it; ++it) {
        if (split) {
          out(i, it.col()) += half * it.value();
          out(it.col(), i) += half * it.value();
        } else {
          out(i, it.col()) += it.value();
        }
      }
  }
}

} // namespace plantar::contact
