#include "apps/output_directory.h"

#include <stdexcept>
#include <string>
#include <vector>

namespace plantar::app {

void prepare_output_directory(const std::filesystem::path& directory) {
  namespace fs = std::filesystem;
  std::error_code error;
  fs::create_directories(directory, error);
  if (error || !fs::is_directory(directory))
    throw std::runtime_error("output directory '" + directory.string() + "': cannot be created (" +
                             error.message() + ")");
  // The marks go first, so that a run killed here is never taken for a finished one.
  for (const char* mark : {"summary.csv", "summary.txt", "failure.txt"})
    fs::remove(directory / mark, error);
  std::vector<fs::path> stale;
  for (const fs::directory_entry& entry : fs::directory_iterator(directory, error)) {
    const std::string name = entry.path().filename().string();
    if (entry.is_directory()
            ? (name == "failed" || name == "vtk")
            : (entry.path().extension() == ".pvd" || name.find(".tmp-") != std::string::npos))
      stale.push_back(entry.path());
  }
  for (const fs::path& path : stale)
    fs::remove_all(path, error);
}

} // namespace plantar::app
