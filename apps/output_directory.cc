#include "apps/output_directory.h"

#include <string>
#include <vector>

namespace plantar::app {

void prepare_output_directory(const std::filesystem::path& directory) {
  namespace fs = std::filesystem;
  std::error_code error;
  if (!fs::is_directory(directory, error))
    return; // the run creates it when it writes its first file
  // The marks go first, so that a run killed here is never taken for a finished one.
  for (const char* mark : {"summary.csv", "summary.txt", "failure.txt"})
    fs::remove(directory / mark, error);
  std::vector<fs::path> stale;
  for (const fs::directory_entry& entry : fs::directory_iterator(directory, error)) {
    const std::string name = entry.path().filename().string();
    if (entry.is_directory() ? (name == "failed" || name == "vtk")
                             : (entry.path().extension() == ".pvd" ||
                                name.find(".tmp-") != std::string::npos))
      stale.push_back(entry.path());
  }
  for (const fs::path& path : stale)
    fs::remove_all(path, error);
}

} // namespace plantar::app
