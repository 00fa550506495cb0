#include "apps/point_process.h"

#include "apps/humanoid_job.h"
#include "fem/atomic_file.h"

#include <cerrno>
#include <csignal>
#include <cstdio>
#include <cstring>
#include <fcntl.h>
#include <fstream>
#include <sstream>
#include <stdexcept>
#include <sys/prctl.h>
#include <sys/wait.h>
#include <unistd.h>
#include <vector>

extern char** environ;

namespace plantar::app {

namespace {

namespace fs = std::filesystem;

/// Last line of @p log starting with "plantar: error:", or its last line.
std::string failure_message(const fs::path& log) {
  std::ifstream in(log);
  std::string line, last, error;
  while (std::getline(in, line)) {
    if (line.find("plantar: error:") == 0)
      error = line.substr(16);
    if (!line.empty())
      last = line;
  }
  return error.empty() ? last : error;
}

/// Whether the environment entry @p entry ("NAME=value") belongs to an MPI launcher.
bool launcher_variable(const char* entry) {
  for (const char* prefix : {"OMPI_", "PMIX_", "PMI_"})
    if (std::strncmp(entry, prefix, std::strlen(prefix)) == 0)
      return true;
  return false;
}

} // namespace

PointProcesses::PointProcesses(fs::path executable, int jobs)
    : executable_(std::move(executable)), jobs_(jobs) {}

void PointProcesses::start(int index, const fs::path& directory) {
  // Everything the child needs is prepared before fork: the child only calls
  // async-signal-safe functions before execve.
  const std::string scene = (directory / "scene.prm").string(),
                    log = (directory / "log.txt").string();
  const std::string dir = directory.string(), exe = executable_.string();
  const char* const argv[] = {exe.c_str(), "run",          scene.c_str(), "-o",
                              dir.c_str(), "--no-figures", nullptr};
  std::vector<char*> env;
  for (char** e = environ; *e; ++e)
    if (!launcher_variable(*e))
      env.push_back(*e);
  env.push_back(nullptr);
  const std::string no_exec = "plantar: error: cannot run '" + exe + "'\n";
  const pid_t parent = ::getpid();
  std::fflush(stdout);
  std::fflush(stderr);
  const pid_t pid = ::fork();
  if (pid < 0)
    throw std::runtime_error(std::string("sweep: cannot start a process: ") + std::strerror(errno));
  if (pid == 0) {
    ::prctl(PR_SET_PDEATHSIG, SIGKILL);
    if (::getppid() != parent)
      ::_exit(127); // the sweep died between fork and prctl
    const int fd = ::open(log.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
    if (fd >= 0) {
      ::dup2(fd, STDOUT_FILENO);
      ::dup2(fd, STDERR_FILENO);
      ::close(fd);
    }
    ::execve(exe.c_str(), const_cast<char* const*>(argv), env.data());
    [[maybe_unused]] const auto n = ::write(STDERR_FILENO, no_exec.data(), no_exec.size());
    ::_exit(127);
  }
  running_[pid] = {index, directory};
}

std::optional<PointProcesses::Finished> PointProcesses::reap(bool block) {
  while (!running_.empty()) {
    int status = 0;
    const pid_t pid = ::waitpid(-1, &status, block ? 0 : WNOHANG);
    if (pid == 0)
      return std::nullopt;
    if (pid < 0) {
      if (errno == EINTR)
        continue;
      throw std::runtime_error("sweep: waitpid failed");
    }
    const auto it = running_.find(pid);
    if (it == running_.end())
      continue; // not a point's process
    Finished finished;
    finished.index = it->second.first;
    const fs::path dir = it->second.second;
    running_.erase(it);
    std::ostringstream report;
    if (WIFEXITED(status) && WEXITSTATUS(status) == 0 && fs::exists(dir / "summary.csv")) {
      finished.ok = true;
      report << "max |a_z| " << read_summary_value(dir / "summary.csv", "max_waist_acceleration_z")
             << " m/s^2, roll difference "
             << read_summary_value(dir / "summary.csv", "roll_difference_deg") << " deg";
    } else if (WIFEXITED(status)) {
      const std::string message = failure_message(dir / "log.txt");
      fem::write_file_atomically(dir / "failure.txt",
                                 [&](std::ostream& os) { os << message << "\n"; });
      report << "FAILED (exit " << WEXITSTATUS(status) << "): " << message;
    } else {
      report << "killed by a signal; rerun the sweep to redo it";
    }
    finished.report = report.str();
    return finished;
  }
  return std::nullopt;
}

} // namespace plantar::app
