#include "tests/contact/siconos_format.h"

#include "contact/coulomb_cone.h"

#include <algorithm>
#include <cfloat>
#include <cmath>
#include <cstdio>
#include <memory>
#include <stdexcept>
#include <vector>

namespace plantar::contact::testing {

namespace {
struct FileCloser {
  void operator()(std::FILE* f) const { std::fclose(f); }
};

class Scanner {
public:
  Scanner(const std::string& path, const char* reader)
      : path_(path), reader_(reader), file_(std::fopen(path.c_str(), "r")) {
    if (!file_)
      throw std::runtime_error(reader_ + ": cannot open " + path);
  }
  int integer(const char* what) {
    int value = 0;
    if (std::fscanf(file_.get(), "%d", &value) != 1)
      fail(what);
    return value;
  }
  // The same conversions as Siconos's reader (%lf; sparse-block values %32le).
  double real(const char* what, bool width_32 = false) {
    double value = 0.0;
    if (std::fscanf(file_.get(), width_32 ? "%32le" : "%lf", &value) != 1)
      fail(what);
    return value;
  }
  [[noreturn]] void fail(const std::string& what) const {
    throw std::runtime_error(reader_ + ": " + path_ + ": expected " + what + " at byte " +
                             std::to_string(std::ftell(file_.get())));
  }

private:
  std::string path_, reader_;
  std::unique_ptr<std::FILE, FileCloser> file_;
};
} // namespace

Eigen::MatrixXd SiconosProblem::dense_w() const {
  return sparse_block ? Eigen::MatrixXd(sparse) : dense;
}

Eigen::VectorXd read_warm_start(const std::string& path, int n_contacts) {
  Scanner in(path, "read_warm_start");
  const int dimension = in.integer("the dimension");
  if (dimension != 3)
    in.fail("dimension 3 (read " + std::to_string(dimension) + ")");
  const int n = in.integer("the number of contacts");
  if (n != n_contacts)
    in.fail("the problem's " + std::to_string(n_contacts) + " contacts (read " + std::to_string(n) +
            ")");
  Eigen::VectorXd impulses(3 * n);
  for (int i = 0; i < 3 * n; ++i)
    impulses[i] = in.real(("impulse " + std::to_string(i)).c_str());
  return impulses;
}

SiconosProblem read_siconos_problem(const std::string& path) {
  Scanner in(path, "read_siconos_problem");
  SiconosProblem out;
  out.dimension = in.integer("the dimension");
  if (out.dimension != 3)
    in.fail("dimension 3 (read " + std::to_string(out.dimension) + ")");
  out.n_contacts = in.integer("the number of contacts");
  const int storage = in.integer("the matrix storage type");
  const int size0 = in.integer("the matrix rows");
  const int size1 = in.integer("the matrix columns");
  if (out.n_contacts < 0 || size0 != 3 * out.n_contacts || size1 != size0)
    in.fail("a square matrix of size 3 n = " + std::to_string(3 * out.n_contacts) + " (read " +
            std::to_string(size0) + "x" + std::to_string(size1) + ")");
  const int n3 = size0;
  if (storage == 0) {
    if (in.integer("the dense rows") != n3 || in.integer("the dense columns") != n3)
      in.fail("the dense matrix sizes repeated");
    out.dense.resize(n3, n3);
    for (int j = 0; j < n3; ++j)
      for (int i = 0; i < n3; ++i)
        out.dense(i, j) = in.real("a dense matrix entry");
  } else if (storage == 1) {
    out.sparse_block = true;
    out.sparse.resize(n3, n3);
    const int n_blocks = in.integer("the number of blocks");
    if (n_blocks > 0) {
      const int block_rows = in.integer("the number of block rows");
      const int block_cols = in.integer("the number of block columns");
      std::vector<int> row_end(block_rows), col_end(block_cols);
      for (int& r : row_end)
        r = in.integer("a cumulative block row size");
      for (int& c : col_end)
        c = in.integer("a cumulative block column size");
      const int filled1 = in.integer("filled1");
      const int filled2 = in.integer("filled2");
      if (filled1 != block_rows + 1 || filled2 != n_blocks)
        in.fail("filled1 = block rows + 1 and filled2 = blocks");
      std::vector<int> row_pointer(filled1), column(filled2);
      for (int& p : row_pointer)
        p = in.integer("a block row pointer");
      for (int& c : column)
        c = in.integer("a block column index");
      std::vector<Eigen::Triplet<double>> entries;
      for (int bi = 0; bi < block_rows; ++bi) {
        const int row0 = bi == 0 ? 0 : row_end[bi - 1];
        const int rows = row_end[bi] - row0;
        for (int b = row_pointer[bi]; b < row_pointer[bi + 1]; ++b) {
          if (b < 0 || b >= n_blocks || column[b] < 0 || column[b] >= block_cols)
            in.fail("block indices inside the matrix");
          const int col0 = column[b] == 0 ? 0 : col_end[column[b] - 1];
          const int cols = col_end[column[b]] - col0;
          if (in.integer("a block number") != b)
            in.fail("block number " + std::to_string(b));
          for (int j = 0; j < cols; ++j)
            for (int i = 0; i < rows; ++i)
              entries.emplace_back(row0 + i, col0 + j, in.real("a block entry", true));
        }
      }
      out.sparse.setFromTriplets(entries.begin(), entries.end());
    }
  } else {
    in.fail("matrix storage 0 (dense) or 1 (sparse block), read " + std::to_string(storage));
  }
  out.q.resize(n3);
  for (int i = 0; i < n3; ++i)
    out.q[i] = in.real("an entry of q");
  out.mu.resize(out.n_contacts);
  for (int k = 0; k < out.n_contacts; ++k)
    out.mu[k] = in.real("a friction coefficient");
  return out;
}

double pose_problem(const SiconosProblem& source, ContactProblem& problem, AsymmetryPolicy policy,
                    double asymmetry_limit) {
  const int n = source.n_contacts;
  problem.resize(n, 0);
  problem.patches.clear();
  problem.patch_levers.clear();
  problem.n_contacts = n;
  problem.free_velocity = source.q;
  problem.friction = source.mu;
  problem.normal_bias.setZero();
  return source.sparse_block ? problem.general.set_sparse(source.sparse, policy, asymmetry_limit)
                             : problem.general.set_dense(source.dense, policy, asymmetry_limit);
}

double fc3d_error(const Eigen::MatrixXd& w, const Eigen::VectorXd& q, const Eigen::VectorXd& mu,
                  const Eigen::VectorXd& r) {
  const Eigen::VectorXd u = w * r + q;
  double sum = 0.0;
  for (Eigen::Index k = 0; k < mu.size(); ++k) {
    const Eigen::Vector3d rk = r.segment<3>(3 * k);
    Eigen::Vector3d uk = u.segment<3>(3 * k);
    uk[0] += mu[k] * std::sqrt(uk[1] * uk[1] + uk[2] * uk[2]);
    sum += (rk - project_onto_cone(rk - uk, mu[k])).squaredNorm();
  }
  const double scale = std::max({q.norm(), u.norm(), r.norm()});
  const double error = std::sqrt(sum);
  return scale > DBL_EPSILON ? error / scale : error;
}

} // namespace plantar::contact::testing
