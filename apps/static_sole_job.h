#pragma once
// The "static sole" scene: mesh the sole, attach its top face, load its
// bottom face with a uniform ground reaction, solve, report and write fields.

#include "apps/scene.h"

#include <filesystem>

namespace plantar::app {

struct StaticSoleResult {
  unsigned int n_cells = 0, n_dofs = 0;
  double max_displacement = 0; ///< m
  double mean_bottom_uz = 0;   ///< m, mean vertical displacement of the bottom nodes
  double reaction_z = 0;       ///< N, on the attached face
  double wall_time = 0;        ///< s
};

/// Runs the scene, writes <output>/sole.vtu (if asked) and returns the figures.
StaticSoleResult run_static_sole(const Scene& scene, const std::filesystem::path& output);

} // namespace plantar::app
