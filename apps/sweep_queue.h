#pragma once
// `mpirun -np N plantar sweep`: the sweep's points handed out over MPI ranks by a
// master-worker queue. Rank 0 owns the sweep (scene, point files, sweep.csv) and hands the next
// unfinished point to whichever rank asks; it also runs points itself, since a point runs in a
// child process and the queue costs rank 0 a few messages per point. Every rank runs up to
// -j children at a time. The ranks share the output directory (a shared file system).

#include "apps/point_process.h"

#include <filesystem>
#include <functional>
#include <string>
#include <vector>

namespace plantar::app {

/// Whether this process was started by an MPI launcher (mpirun, mpiexec, srun): one of
/// OMPI_COMM_WORLD_SIZE (Open MPI), PMIX_RANK (PMIx) or PMI_RANK (PMI-1/2, MPICH, Slurm) is set.
/// Without a launcher the sweep does not initialise MPI (a singleton MPI_Init would start a
/// daemon for nothing).
bool launched_by_mpi();

/// MPI_Init on construction, MPI_Finalize on destruction (one per process).
class MpiSession {
public:
  MpiSession(int& argc, char**& argv);
  ~MpiSession();
  MpiSession(const MpiSession&) = delete;
  MpiSession& operator=(const MpiSession&) = delete;
};

/// This process's rank in MPI_COMM_WORLD, or 0 if MPI is not initialised.
int sweep_rank();
/// The number of ranks of MPI_COMM_WORLD, or 1 if MPI is not initialised.
int sweep_ranks();

/// One point finished (on any rank), as reported to rank 0.
struct FinishedPoint {
  int index = 0;      ///< index into the list given to run_points_on_ranks
  int rank = 0;       ///< the rank that ran it
  std::string report; ///< PointProcesses::Finished::report
};

/// Rank 0: runs the points in @p directories (each holding scene.prm) on every rank, up to
/// @p jobs child processes of @p executable per rank, handing out the next one in order to the
/// first rank with a free slot; calls @p on_finished on rank 0 as each point ends. Returns
/// once every point has ended and every other rank has been told to stop. An error on rank 0
/// after the first point has been handed out aborts the job (MPI_Abort, exit status 1) after
/// printing its message once.
void run_points_on_ranks(const std::vector<std::filesystem::path>& directories, int jobs,
                         const std::filesystem::path& executable,
                         const std::function<void(const FinishedPoint&)>& on_finished);

/// Ranks 1..N-1: asks rank 0 for points and runs them, up to @p jobs at a time, until told to
/// stop. Returns the exit status rank 0 sent with its stop (0, or 1 if rank 0 failed before
/// handing out points and printed the error). Errors on this rank abort the job.
int run_sweep_worker(int jobs, const std::filesystem::path& executable);

/// Rank 0, on an error: tells every other rank to exit with @p status without a message (rank 0
/// prints it once). Does nothing once run_points_on_ranks has begun (its end has stopped the
/// other ranks already) or on a second call.
void stop_sweep_workers(int status);

} // namespace plantar::app
