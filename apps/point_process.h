#pragma once
// The child processes of `plantar sweep`: each grid point runs as
// `plantar run DIR/points/<id>/scene.prm -o DIR/points/<id> --no-figures`, its output in
// DIR/points/<id>/log.txt, so that a crashing point never takes the sweep (or its MPI rank) down.

#include <filesystem>
#include <map>
#include <optional>
#include <string>
#include <sys/types.h>

namespace plantar::app {

/// Up to `jobs` points running at a time as child processes of this process.
class PointProcesses {
public:
  /// @p executable: the plantar binary; @p jobs >= 1: the most children at a time.
  PointProcesses(std::filesystem::path executable, int jobs);

  bool has_free_slot() const { return static_cast<int>(running_.size()) < jobs_; }
  bool empty() const { return running_.empty(); }

  /// Starts point @p index whose directory @p directory holds scene.prm. The child runs with
  /// the MPI launcher's variables (OMPI_*, PMIX_*, PMI_*) removed from its environment, so it
  /// is never taken for a rank of this job, and is killed (SIGKILL) when this process dies.
  /// Throws std::runtime_error if no process can be started.
  void start(int index, const std::filesystem::path& directory);

  struct Finished {
    int index = 0;      ///< as given to start()
    bool ok = false;    ///< exit status 0 and summary.csv written
    std::string report; ///< one line: peak |a_z| and roll difference, or why it failed
  };

  /// Waits for one child to end (if @p block; otherwise returns nothing unless one has already
  /// ended). A child that exits with a non-zero status gets DIR/failure.txt (its log's
  /// "plantar: error:" line, written atomically); one killed by a signal gets nothing, so a
  /// rerun of the sweep redoes it. Returns nothing if no child is running.
  std::optional<Finished> reap(bool block);

private:
  std::filesystem::path executable_;
  int jobs_;
  std::map<pid_t, std::pair<int, std::filesystem::path>> running_;
};

} // namespace plantar::app
