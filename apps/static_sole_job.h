#pragma once
// The "static sole" scene: mesh the sole, attach its top face, load its
// bottom face with a uniform ground reaction, solve, report and write fields.

#include "apps/scene.h"
#include "fem/material_table.h"
#include "fem/mesh_import.h"

#include <filesystem>

namespace plantar::app {

struct StaticSoleResult {
  unsigned int n_cells = 0, n_dofs = 0;
  double max_displacement = 0; ///< m
  double mean_bottom_uz = 0;   ///< m, mean vertical displacement of the bottom nodes
  double reaction_z = 0;       ///< N, on the attached face
  double wall_time = 0;        ///< s
};

/// The linear sole's materials: Sole/Materials against the mesh's physical groups @p groups.
/// @throws std::invalid_argument naming Sole/Materials and the geometry file.
fem::MaterialTable sole_material_table(const Scene& scene, const fem::PhysicalGroups& groups);

/// Runs the scene, writes <output>/sole.vtu (if asked) and returns the figures.
StaticSoleResult run_static_sole(const Scene& scene, const std::filesystem::path& output);

} // namespace plantar::app
