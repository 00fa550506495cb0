#include "apps/sweep_queue.h"

#include "fem/exception_text.h"

#include <mpi.h>

#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <iostream>
#include <stdexcept>
#include <thread>

namespace plantar::app {

namespace {

namespace fs = std::filesystem;

// Messages (all between rank 0 and one other rank; MPI keeps their order):
//   worker -> 0  request  (no data)                 a free slot: send me a point
//   worker -> 0  done     "<index>\n<report>"        a point of this rank ended
//   0 -> worker  work     "<index>\n<directory>"     run this point
//   0 -> worker  stop     int exit status            no point left (0) or rank 0 failed (1)
enum Tag : int { request = 1, done = 2, work = 3, stop = 4 };

/// Idle wait between polls: MPI's blocking calls spin a core, which the points need.
void pause() {
  std::this_thread::sleep_for(std::chrono::milliseconds(2));
}

void send_text(const std::string& text, int destination, Tag tag) {
  MPI_Send(text.data(), static_cast<int>(text.size()), MPI_CHAR, destination, tag, MPI_COMM_WORLD);
}

std::string receive_text(const MPI_Status& status) {
  int size = 0;
  MPI_Get_count(&status, MPI_CHAR, &size);
  std::string text(static_cast<std::size_t>(size), '\0');
  MPI_Recv(text.data(), size, MPI_CHAR, status.MPI_SOURCE, status.MPI_TAG, MPI_COMM_WORLD,
           MPI_STATUS_IGNORE);
  return text;
}

/// "<index>\n<rest>" -> (index, rest).
std::pair<int, std::string> split(const std::string& text) {
  const auto newline = text.find('\n');
  return {std::stoi(text.substr(0, newline)), text.substr(newline + 1)};
}

/// Whether run_points_on_ranks has begun: from then on the other ranks are stopped by the queue
/// (or the job aborted), never by stop_sweep_workers.
bool queue_started = false;

[[noreturn]] void abort_job(const std::string& message) {
  std::cerr << "plantar: error: sweep (rank " << sweep_rank() << "): " << message << std::endl;
  MPI_Abort(MPI_COMM_WORLD, 1);
  std::_Exit(1);
}

} // namespace

bool launched_by_mpi() {
  for (const char* name : {"OMPI_COMM_WORLD_SIZE", "PMIX_RANK", "PMI_RANK"})
    if (std::getenv(name))
      return true;
  return false;
}

MpiSession::MpiSession(int& argc, char**& argv) {
  MPI_Init(&argc, &argv);
}

MpiSession::~MpiSession() {
  MPI_Finalize();
}

int sweep_rank() {
  int initialised = 0, finalised = 0, rank = 0;
  MPI_Initialized(&initialised);
  MPI_Finalized(&finalised);
  if (initialised && !finalised)
    MPI_Comm_rank(MPI_COMM_WORLD, &rank);
  return rank;
}

int sweep_ranks() {
  int initialised = 0, finalised = 0, size = 1;
  MPI_Initialized(&initialised);
  MPI_Finalized(&finalised);
  if (initialised && !finalised)
    MPI_Comm_size(MPI_COMM_WORLD, &size);
  return size;
}

void stop_sweep_workers(int status) {
  if (queue_started)
    return;
  queue_started = true; // once
  for (int rank = 1; rank < sweep_ranks(); ++rank)
    MPI_Send(&status, 1, MPI_INT, rank, stop, MPI_COMM_WORLD);
}

void run_points_on_ranks(const std::vector<fs::path>& directories, int jobs,
                         const fs::path& executable,
                         const std::function<void(const FinishedPoint&)>& on_finished) {
  queue_started = true;
  try {
    PointProcesses local(executable, jobs);
    const int n = static_cast<int>(directories.size());
    int next = 0, n_finished = 0, n_working = sweep_ranks() - 1;
    while (n_finished < n || n_working > 0) {
      bool idle = true;
      while (next < n && local.has_free_slot()) {
        local.start(next, directories[static_cast<std::size_t>(next)]);
        ++next;
      }
      if (const auto finished = local.reap(false)) {
        on_finished({finished->index, 0, finished->report});
        ++n_finished;
        idle = false;
      }
      int flag = 0;
      MPI_Status status;
      MPI_Iprobe(MPI_ANY_SOURCE, MPI_ANY_TAG, MPI_COMM_WORLD, &flag, &status);
      if (flag) {
        idle = false;
        const std::string text = receive_text(status);
        if (status.MPI_TAG == done) {
          const auto [index, report] = split(text);
          on_finished({index, status.MPI_SOURCE, report});
          ++n_finished;
        } else if (next < n) {
          send_text(std::to_string(next) + "\n" +
                        directories[static_cast<std::size_t>(next)].string(),
                    status.MPI_SOURCE, work);
          ++next;
        } else {
          const int zero = 0;
          MPI_Send(&zero, 1, MPI_INT, status.MPI_SOURCE, stop, MPI_COMM_WORLD);
          --n_working;
        }
      }
      if (idle)
        pause();
    }
  } catch (const std::exception& e) {
    abort_job(fem::exception_text(e));
  }
}

int run_sweep_worker(int jobs, const fs::path& executable) {
  try {
    PointProcesses local(executable, jobs);
    const auto report = [](const PointProcesses::Finished& finished) {
      send_text(std::to_string(finished.index) + "\n" + finished.report, 0, done);
    };
    bool stopped = false;
    while (!stopped || !local.empty()) {
      if (stopped || !local.has_free_slot()) {
        if (const auto finished = local.reap(true))
          report(*finished);
        continue;
      }
      MPI_Send(nullptr, 0, MPI_CHAR, 0, request, MPI_COMM_WORLD);
      for (;;) { // the answer, reporting the points that end meanwhile
        int flag = 0;
        MPI_Status status;
        MPI_Iprobe(0, MPI_ANY_TAG, MPI_COMM_WORLD, &flag, &status);
        if (flag && status.MPI_TAG == stop) {
          int code = 0;
          MPI_Recv(&code, 1, MPI_INT, 0, stop, MPI_COMM_WORLD, MPI_STATUS_IGNORE);
          if (code != 0)
            return code;
          stopped = true;
          break;
        }
        if (flag) {
          const auto [index, directory] = split(receive_text(status));
          local.start(index, directory);
          break;
        }
        if (const auto finished = local.reap(false))
          report(*finished);
        else
          pause();
      }
    }
    return 0;
  } catch (const std::exception& e) {
    abort_job(fem::exception_text(e));
  }
}

} // namespace plantar::app
