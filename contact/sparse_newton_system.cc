#include "contact/sparse_newton_system.h"

#include <algorithm>

namespace plantar::contact {

bool SparseNewtonSystem::applicable(const ContactProblem& problem) {
  return problem.general.storage() == GeneralDelassus::Storage::sparse &&
         problem.rigid_rank() == 0 && problem.patches.empty();
}

double SparseNewtonSystem::block_density(const ContactProblem& problem) {
  if (!applicable(problem) || problem.n_contacts == 0)
    return 0.0;
  const auto& w = problem.general.sparse();
  const int n = problem.n_contacts;
  long blocks = 0;
  std::vector<int> last(static_cast<std::size_t>(n), -1);
  for (int k = 0; k < n; ++k) // contact rows 3k..3k+2: distinct block columns
    for (int i = 3 * k; i < 3 * k + 3; ++i)
      for (GeneralDelassus::SparseMatrix::InnerIterator it(w, i); it; ++it) {
        const int l = static_cast<int>(it.col()) / 3;
        if (last[static_cast<std::size_t>(l)] != k) {
          last[static_cast<std::size_t>(l)] = k;
          ++blocks;
        }
      }
  return static_cast<double>(blocks) / (static_cast<double>(n) * n);
}

void SparseNewtonSystem::prepare(const ContactProblem& problem) {
  const auto& w = problem.general.sparse(); // row-major
  n_ = problem.n_contacts;
  // Blocks by block row first (row-major storage), then regrouped by block column.
  std::vector<std::vector<std::pair<int, Eigen::Matrix3d>>> by_column(static_cast<std::size_t>(n_));
  std::vector<int> slot(static_cast<std::size_t>(n_), -1);
  for (int k = 0; k < n_; ++k) {
    std::vector<int> touched;
    for (int r = 0; r < 3; ++r)
      for (GeneralDelassus::SparseMatrix::InnerIterator it(w, 3 * k + r); it; ++it) {
        const int l = static_cast<int>(it.col()) / 3;
        auto& column = by_column[static_cast<std::size_t>(l)];
        if (slot[static_cast<std::size_t>(l)] < 0) {
          slot[static_cast<std::size_t>(l)] = static_cast<int>(column.size());
          column.emplace_back(k, Eigen::Matrix3d::Zero());
          touched.push_back(l);
        }
        column[static_cast<std::size_t>(slot[static_cast<std::size_t>(l)])].second(
            r, static_cast<int>(it.col()) - 3 * l) = it.value();
      }
    if (slot[static_cast<std::size_t>(k)] < 0) { // the diagonal block, even if not stored
      by_column[static_cast<std::size_t>(k)].emplace_back(k, Eigen::Matrix3d::Zero());
      touched.push_back(k);
    }
    for (const int l : touched)
      slot[static_cast<std::size_t>(l)] = -1;
  }
  column_start_.assign(static_cast<std::size_t>(n_) + 1, 0);
  column_row_.clear();
  blocks_.clear();
  for (int l = 0; l < n_; ++l) { // rows ascending within each column (k visited in order)
    for (const auto& [k, block] : by_column[static_cast<std::size_t>(l)]) {
      column_row_.push_back(k);
      blocks_.push_back(block);
    }
    column_start_[static_cast<std::size_t>(l) + 1] = static_cast<int>(column_row_.size());
  }
  position_.assign(static_cast<std::size_t>(n_), -1);
  pattern_active_.clear();
  pattern_valid_ = false;
  n_analyses_ = 0;
}

bool SparseNewtonSystem::factorize(const int* active, int n_active, const Eigen::MatrixXd& a_blocks,
                                   const Eigen::MatrixXd& b_blocks, double delta) {
  const bool same = pattern_valid_ && static_cast<int>(pattern_active_.size()) == n_active &&
                    std::equal(active, active + n_active, pattern_active_.begin());
  if (!same) { // the pattern of J_AA: W's blocks between active contacts
    std::fill(position_.begin(), position_.end(), -1);
    for (int i = 0; i < n_active; ++i)
      position_[static_cast<std::size_t>(active[i])] = i;
    pattern_active_.assign(active, active + n_active);
    entries_.clear();
    entry_start_.assign(static_cast<std::size_t>(n_active) + 1, 0);
    for (int j = 0; j < n_active; ++j) {
      const int l = active[j];
      for (int b = column_start_[static_cast<std::size_t>(l)];
           b < column_start_[static_cast<std::size_t>(l) + 1]; ++b) {
        const int k = column_row_[static_cast<std::size_t>(b)];
        const int i = position_[static_cast<std::size_t>(k)];
        if (i >= 0)
          entries_.push_back(Entry{i, k, b, k == l});
      }
      entry_start_[static_cast<std::size_t>(j) + 1] = static_cast<int>(entries_.size());
    }
    const int size = 3 * n_active;
    matrix_.resize(size, size);
    matrix_.resizeNonZeros(static_cast<Eigen::Index>(9 * entries_.size()));
    int* outer = matrix_.outerIndexPtr();
    int* inner = matrix_.innerIndexPtr();
    for (int j = 0; j < n_active; ++j) {
      const int e0 = entry_start_[static_cast<std::size_t>(j)];
      const int count = entry_start_[static_cast<std::size_t>(j) + 1] - e0;
      for (int c = 0; c < 3; ++c) {
        const int start = 9 * e0 + 3 * count * c;
        outer[3 * j + c] = start;
        for (int e = 0; e < count; ++e)
          for (int r = 0; r < 3; ++r)
            inner[start + 3 * e + r] =
                3 * entries_[static_cast<std::size_t>(e0 + e)].row_position + r;
      }
    }
    outer[size] = static_cast<int>(9 * entries_.size());
  }
  double* values = matrix_.valuePtr();
  const int* outer = matrix_.outerIndexPtr();
  for (int j = 0; j < n_active; ++j) {
    const int e0 = entry_start_[static_cast<std::size_t>(j)];
    const int count = entry_start_[static_cast<std::size_t>(j) + 1] - e0;
    for (int e = 0; e < count; ++e) {
      const Entry& entry = entries_[static_cast<std::size_t>(e0 + e)];
      Eigen::Matrix3d block = b_blocks.middleCols<3>(3 * entry.row_contact) *
                              blocks_[static_cast<std::size_t>(entry.block)];
      if (entry.diagonal) {
        block += a_blocks.middleCols<3>(3 * entry.row_contact);
        block.diagonal().array() += delta;
      }
      for (int c = 0; c < 3; ++c)
        for (int r = 0; r < 3; ++r)
          values[outer[3 * j + c] + 3 * e + r] = block(r, c);
    }
  }
  if (!same) {
    lu_.analyzePattern(matrix_);
    ++n_analyses_;
    pattern_valid_ = true;
  }
  lu_.factorize(matrix_);
  return lu_.info() == Eigen::Success;
}

void SparseNewtonSystem::solve(Eigen::Ref<Eigen::VectorXd> x) {
  solution_ = lu_.solve(x);
  x = solution_;
}

} // namespace plantar::contact
