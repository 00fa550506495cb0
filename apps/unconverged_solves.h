#pragma once
// The contact solves of a humanoid run that stopped above Contact/Tolerance (below Contact/
// Failure residual, or the one that stopped the run), listed in unconverged_solves.csv.

#include "contact/solver_settings.h"

#include <filesystem>
#include <vector>

namespace plantar::app {

/// One unconverged contact solve.
struct UnconvergedSolve {
  int step = 0;        ///< the step that ended with this solve (1-based, as in the summary)
  double time = 0;     ///< s, the step's end
  double residual = 0; ///< m/s, natural-map residual (max over contacts)
  int n_contacts = 0;  ///< active contacts
  int iterations = 0;  ///< sweeps or iterations (auto: GS sweeps plus Newton iterations)
  contact::SolverStatus status = contact::SolverStatus::max_iterations;
  contact::ContactSolverType finished_by = contact::ContactSolverType::gauss_seidel;
  contact::SwitchReason switch_reason = contact::SwitchReason::none; ///< auto only
  int switch_iteration = 0; ///< auto: GS sweeps before the switch
};

class UnconvergedSolves {
public:
  /// Room for @p capacity entries (a run's steps): add() then allocates nothing.
  explicit UnconvergedSolves(int capacity = 0) { list_.reserve(capacity); }
  /// Appends @p solve; past the capacity it is only counted (n_dropped).
  void add(const UnconvergedSolve& solve) {
    if (list_.size() < list_.capacity())
      list_.push_back(solve);
    else
      ++n_dropped_;
  }
  const std::vector<UnconvergedSolve>& list() const { return list_; }
  int n_dropped() const { return n_dropped_; }
  /// Writes the list to @p path atomically: header "step,t,residual,n_contacts,iterations,
  /// status,finished_by,switch_reason,switch_iteration" and one row per solve.
  void write_csv(const std::filesystem::path& path) const;

private:
  std::vector<UnconvergedSolve> list_;
  int n_dropped_ = 0;
};

} // namespace plantar::app
