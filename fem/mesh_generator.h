#pragma once
// Meshes are generated from the gmsh .geo sources in meshes/ when a scene
// needs them, and cached: the cache key hashes the .geo text, the parameter
// values and the gmsh version, so an edited .geo or parameter regenerates.

#include <filesystem>
#include <map>
#include <string>

namespace plantar::fem {

struct MeshRequest {
  std::filesystem::path geo_file;        ///< gmsh .geo source
  std::map<std::string, double> numbers; ///< gmsh -setnumber NAME VALUE
  std::filesystem::path cache_directory; ///< where generated .msh files live
  std::string gmsh_executable = "gmsh";
  double time_limit = 300; ///< s of wall time gmsh may take (coreutils timeout)
};

/// Returns the path of an MSH 2.2 file meshed from the request (3D mesh),
/// generating it with the gmsh executable if it is not in the cache yet.
/// Throws std::runtime_error naming the .geo file and gmsh's message if the
/// file is missing or gmsh fails, produces no elements or runs past the time
/// limit (a geometry far larger than its mesh sizes: a .geo in mm, say).
std::filesystem::path generate_mesh(const MeshRequest& request);

} // namespace plantar::fem
