#pragma once
// A one-line progress bar on stderr for long runs: simulated time, real-time factor
// (simulated seconds per wall second) and the estimated wall time left. Quiet unless both
// stdout and stderr are terminals.

#include <chrono>
#include <string>

namespace plantar::app {

class ProgressBar {
public:
  /// @p label names the run (e.g. the foot form), @p end_time the simulated end (s).
  /// @p enabled: draw at all (default: stdout and stderr are terminals).
  ProgressBar(std::string label, double end_time, bool enabled = terminal());
  /// Redraws for simulated time @p t (s), at most every 0.2 s of wall time. No allocation.
  void update(double t);
  /// Clears the line.
  void finish();
  bool enabled() const { return enabled_; }
  /// True when stdout and stderr are both terminals.
  static bool terminal();

private:
  std::string label_;
  double end_time_;
  bool enabled_;
  bool drawn_ = false;
  std::chrono::steady_clock::time_point start_, last_;
};

} // namespace plantar::app
