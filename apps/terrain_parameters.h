#pragma once
// Subsection "Terrain" of a humanoid scene: the ground the robot stands and walks on
// (contact/terrain.h, docs/terrain.md). Type = flat | slope | steps | bumps | cylinder | rough |
// grid and each type's parameters; the defaults are contact::TerrainParameters' (written there
// once).

#include "contact/terrain_factory.h"

#include <deal.II/base/parameter_handler.h>

#include <filesystem>

namespace plantar::app {

struct TerrainSceneParameters {
  contact::TerrainParameters terrain;
  static void declare(dealii::ParameterHandler& prm);
  /// Reads the entries; Grid file resolved like the scene's other paths (the scene's directory,
  /// then the Plantar tree). Throws std::invalid_argument naming Terrain/<entry>, the value and
  /// its range (the grid file is read when the terrain is made: make_terrain).
  void parse(dealii::ParameterHandler& prm, const std::filesystem::path& scene_directory);
};

/// The scene name of @p type ("flat", "slope", ...).
const char* to_string(contact::TerrainType type);

} // namespace plantar::app
