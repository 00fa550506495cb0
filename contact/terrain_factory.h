#pragma once
// The terrain of a scene: its type (an enum parsed once) and parameters, each default written
// here once, and make_terrain() building the Terrain. A new terrain type is a new Terrain file,
// a TerrainType value with its name in terrain_type_names(), its parameters here and one branch
// of make_terrain.

#include "contact/rough_terrain.h"
#include "contact/terrain.h"

#include <memory>
#include <string>
#include <utility>
#include <vector>

namespace plantar::contact {

enum class TerrainType { flat, slope, steps, bumps, cylinder, rough, grid };

/// (value, scene name) of every TerrainType: "flat", "slope", "steps", "bumps", "cylinder",
/// "rough", "grid".
const std::vector<std::pair<TerrainType, const char*>>& terrain_type_names();

/// Every terrain's parameters (the ones of the chosen type are used). Angles in degrees.
struct TerrainParameters {
  TerrainType type = TerrainType::flat;
  double level = 0.0;     ///< z0, m: the ground level (flat), the base of the others
  double origin_x = 0.0;  ///< m: slope's pivot, step edge, cylinder axis, rough centre, grid
  double origin_y = 0.0;  ///< origin (its first value)
  double slope_angle = 5; ///< deg, (-90, 90): rotation about the slope axis
  double slope_axis_heading = 90; ///< deg: the slope axis' angle from x (90: ground falls to +x)
  double step_height = 0.02;      ///< m: rise of the upper level
  double step_heading = 0;        ///< deg: direction of the upper side (0: +x)
  double step_width = 0.002;      ///< m, >= 0: width of the C1 ramp (0: a sharp edge)
  double bump_amplitude = 0.01;   ///< m
  double bump_wavelength_x = 0.5; ///< m, >= 0 (0: none)
  double bump_wavelength_y = 0.5; ///< m, >= 0 (0: none)
  double cylinder_radius = 0.1;   ///< m, > 0
  double cylinder_height = 0.01;  ///< m, (0, radius]: rise of the bump above the level
  double cylinder_heading = 90;   ///< deg: the axis' angle from x (90: along y)
  RoughTerrainParameters rough;   ///< rms, correlation length, seed, modes, size
  std::string grid_file;          ///< CSV heights (grid_terrain.h), resolved by the caller
  double grid_spacing = 0.01;     ///< m, > 0
};

/// The terrain of @p parameters. Throws std::invalid_argument naming the parameter, value and
/// range (the grid: the file, line and column).
std::unique_ptr<Terrain> make_terrain(const TerrainParameters& parameters);

} // namespace plantar::contact
