#include "contact/terrain_factory.h"

#include "contact/bump_terrain.h"
#include "contact/cylinder_terrain.h"
#include "contact/flat_terrain.h"
#include "contact/grid_terrain.h"
#include "contact/slope_terrain.h"
#include "contact/step_terrain.h"

#include <cmath>
#include <stdexcept>
#include <string>

namespace plantar::contact {

const std::vector<std::pair<TerrainType, const char*>>& terrain_type_names() {
  static const std::vector<std::pair<TerrainType, const char*>> names{
      {TerrainType::flat, "flat"},         {TerrainType::slope, "slope"},
      {TerrainType::steps, "steps"},       {TerrainType::bumps, "bumps"},
      {TerrainType::cylinder, "cylinder"}, {TerrainType::rough, "rough"},
      {TerrainType::grid, "grid"}};
  return names;
}

std::unique_ptr<Terrain> make_terrain(const TerrainParameters& p) {
  constexpr double degree = M_PI / 180.0;
  const Eigen::Vector2d origin(p.origin_x, p.origin_y);
  switch (p.type) {
  case TerrainType::flat:
    return std::make_unique<FlatTerrain>(p.level);
  case TerrainType::slope:
    return std::make_unique<SlopeTerrain>(p.slope_angle * degree, p.slope_axis_heading * degree,
                                          Eigen::Vector3d(p.origin_x, p.origin_y, p.level));
  case TerrainType::steps:
    return std::make_unique<StepTerrain>(p.step_height, p.step_heading * degree, origin, p.level,
                                         p.step_width);
  case TerrainType::bumps:
    return std::make_unique<BumpTerrain>(p.bump_amplitude, p.bump_wavelength_x, p.bump_wavelength_y,
                                         p.level);
  case TerrainType::cylinder:
    return std::make_unique<CylinderTerrain>(p.cylinder_radius, p.cylinder_height,
                                             p.cylinder_heading * degree, origin, p.level);
  case TerrainType::rough: {
    RoughTerrainParameters rough = p.rough;
    rough.centre_x = p.origin_x;
    rough.centre_y = p.origin_y;
    rough.level = p.level;
    return std::make_unique<RoughTerrain>(rough);
  }
  case TerrainType::grid:
    return std::make_unique<GridTerrain>(p.grid_file, p.grid_spacing, origin, p.level);
  }
  throw std::invalid_argument("make_terrain: unknown terrain type " +
                              std::to_string(static_cast<int>(p.type)));
}

} // namespace plantar::contact
