#pragma once
// Validity guards of a humanoid run (docs/reliability.md): a model (a foot model through
// FootModel::check_validity) reports after every step the quantities that bound its validity,
// each against a ValidityLimit (a warning level and a failure level, both scene parameters).
//
//   value past `warning` (and not past `failure`): recorded; the run goes on; summary.txt
//     gives the first step, time and value, the peak and the number of steps past it;
//   value past `failure`: the run stops with std::runtime_error naming the quantity, its value,
//     the parameter of the limit and the remedy (e.g. "use Sole/Model = hyperelastic").
//
// "Past" is above for a maximum (Bound::upper, e.g. compression / thickness) and below for a
// minimum (Bound::lower, e.g. det F). The monitor keeps a fixed number of records (one per
// limit, keyed by the limit's address during the run, each with a copy of its limit so that a
// summary outlives the models): check() allocates nothing.

#include <array>
#include <string>

namespace plantar::app {

/// One quantity's limits (the texts are string literals).
struct ValidityLimit {
  enum class Bound { upper, lower };
  const char* key = "";      ///< summary.csv name stem, e.g. "sole_compression"
  const char* quantity = ""; ///< what is measured, e.g. "linear sole compression / thickness"
  const char* warning_parameter = ""; ///< e.g. "Sole/Compression warning"
  const char* failure_parameter = ""; ///< e.g. "Sole/Max compression"
  Bound bound = Bound::upper;
  double warning = 0;      ///< the warning level (same unit as the value)
  double failure = 0;      ///< the failure level
  const char* remedy = ""; ///< what to use instead, appended to the failure message
  /// Whether @p value is past @p level in this limit's direction.
  bool past(double value, double level) const {
    return bound == Bound::upper ? value > level : value < level;
  }
};

/// What the monitor saw of one limit over the run.
struct ValidityRecord {
  const void* id = nullptr; ///< the address of the limit checked (lookup during the run)
  ValidityLimit limit;
  double peak = 0;            ///< largest (upper) or smallest (lower) value seen
  double peak_time = 0;       ///< s
  int n_checks = 0;           ///< steps at which the value was reported
  int n_warning_steps = 0;    ///< steps past the warning level
  int first_warning_step = 0; ///< 0: never past it
  double first_warning_time = 0;
  double first_warning_value = 0;
  bool warned() const { return n_warning_steps > 0; }
};

class ValidityMonitor {
public:
  static constexpr int max_limits = 16;

  /// Sets the step and time (s) that the next check() calls refer to.
  void set_step(int step, double time) {
    step_ = step;
    time_ = time;
  }
  /// Records @p value (the quantity of @p limit at this step; @p detail, e.g. "right sole",
  /// is named in a failure). Throws std::runtime_error if it is past limit.failure (message:
  /// quantity, value, parameter and level, detail, remedy; the caller adds step and time), or
  /// std::logic_error past max_limits distinct limits. No heap allocation unless it throws.
  void check(const ValidityLimit& limit, double value, const char* detail = "");

  int size() const { return n_records_; }
  const ValidityRecord& record(int i) const { return records_[i]; }
  /// Limits whose warning level was crossed.
  int n_warnings() const;
  /// One line per crossed warning level ("warning: ..."), empty if none.
  std::string warning_text() const;

private:
  std::array<ValidityRecord, max_limits> records_{};
  int n_records_ = 0;
  int step_ = 0;
  double time_ = 0;
};

} // namespace plantar::app
