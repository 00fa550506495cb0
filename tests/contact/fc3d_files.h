#pragma once
// The shared third-party problems (../shared/data/fc3d, README there): their paths.

#include <algorithm>
#include <filesystem>
#include <stdexcept>
#include <string>
#include <vector>

namespace plantar::contact::testing {

/// Directory of the shared Siconos-format problems (PLANTAR_FC3D_DATA at configure time).
inline std::string fc3d_data_dir() {
  return PLANTAR_FC3D_DATA;
}

/// Every *.dat file of fc3d_data_dir(), sorted; throws if the directory holds none.
inline std::vector<std::string> fc3d_files() {
  std::vector<std::string> files;
  if (std::filesystem::is_directory(fc3d_data_dir()))
    for (const auto& entry : std::filesystem::directory_iterator(fc3d_data_dir()))
      if (entry.path().extension() == ".dat")
        files.push_back(entry.path().string());
  if (files.empty())
    throw std::runtime_error("no .dat problem in " + fc3d_data_dir());
  std::sort(files.begin(), files.end());
  return files;
}

inline std::string fc3d_name(const std::string& path) {
  return std::filesystem::path(path).stem().string();
}

} // namespace plantar::contact::testing
