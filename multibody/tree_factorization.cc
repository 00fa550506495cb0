#include "multibody/tree_factorization.h"

#include "multibody/kinematics.h"

#include <cmath>

namespace plantar::multibody {

// Storage: factor_(j, i) for j an ancestor of i (upper triangle, column i holds dof i's
// ancestors): A_ji on input, L_ij after compute(); D_i on the diagonal.

TreeFactorization::TreeFactorization(const Model& model)
    : parent_(model.nv, -1), factor_(Eigen::MatrixXd::Zero(model.nv, model.nv)),
      sqrt_d_(Eigen::VectorXd::Zero(model.nv)) {
  for (int b = 1; b < model.n_bodies; ++b) {
    const int first = model.idx_v[b];
    const int p = model.parent[b];
    parent_[first] = p > 0 ? model.idx_v[p] + model.nv_joint[p] - 1 : -1;
    for (int k = 1; k < model.nv_joint[b]; ++k) {
      parent_[first + k] = first + k - 1;
    }
  }
}

bool TreeFactorization::compute(const Eigen::Ref<const Eigen::MatrixXd>& a) {
  const int n = size();
  check_size(a.rows(), n, "TreeFactorization::compute: rows");
  check_size(a.cols(), n, "TreeFactorization::compute: cols");
  // Featherstone 2005, table 2 (LTDL), on the upper triangle: for k from the leaves up,
  // eliminate dof k from its ancestors i: A_ji -= (A_ik / d_k) A_jk for j ancestor of i.
  double* f = factor_.data();
  for (int k = 0; k < n; ++k) { // A_jk for j = k and its ancestors: the entries L and D use
    for (int j = k; j >= 0; j = parent_[j]) {
      f[j + n * k] = a(j, k);
    }
  }
  for (int k = n - 1; k >= 0; --k) {
    const double dk = f[k + n * k];
    if (!(dk > 0.0)) {
      return false;
    }
    double* column_k = f + n * k;
    // The ancestors i of k from k up: column_k[j] for j < i is still A_jk.
    for (int i = parent_[k]; i >= 0; i = parent_[i]) {
      const double ratio = column_k[i] / dk;
      double* column_i = f + n * i;
      for (int j = i; j >= 0; j = parent_[j]) {
        column_i[j] -= ratio * column_k[j];
      }
      column_k[i] = ratio;
    }
    sqrt_d_[k] = std::sqrt(dk);
  }
  return true;
}

void TreeFactorization::half_solve_in_place(Eigen::Ref<Eigen::MatrixXd> x) const {
  const int n = size();
  check_size(x.rows(), n, "TreeFactorization::half_solve_in_place: rows");
  const double* f = factor_.data();
  for (Eigen::Index c = 0; c < x.cols(); ++c) {
    double* xc = x.col(c).data();
    // L^T y = x from the leaves up: y_i is final once its descendants are done.
    for (int i = n - 1; i >= 0; --i) {
      const double xi = xc[i];
      if (xi == 0.0) {
        continue;
      }
      const double* column_i = f + n * i;
      for (int j = parent_[i]; j >= 0; j = parent_[j]) {
        xc[j] -= column_i[j] * xi;
      }
    }
    for (int i = 0; i < n; ++i) {
      xc[i] /= sqrt_d_[i];
    }
  }
}

void TreeFactorization::half_solve_transpose_in_place(Eigen::Ref<Eigen::MatrixXd> x) const {
  const int n = size();
  check_size(x.rows(), n, "TreeFactorization::half_solve_transpose_in_place: rows");
  const double* f = factor_.data();
  for (Eigen::Index c = 0; c < x.cols(); ++c) {
    double* xc = x.col(c).data();
    for (int i = 0; i < n; ++i) {
      xc[i] /= sqrt_d_[i];
    }
    // L x = y from the root down.
    for (int i = 0; i < n; ++i) {
      const double* column_i = f + n * i;
      double sum = xc[i];
      for (int j = parent_[i]; j >= 0; j = parent_[j]) {
        sum -= column_i[j] * xc[j];
      }
      xc[i] = sum;
    }
  }
}

void TreeFactorization::solve_in_place(Eigen::Ref<Eigen::MatrixXd> x) const {
  half_solve_in_place(x);
  half_solve_transpose_in_place(x);
}

} // namespace plantar::multibody
