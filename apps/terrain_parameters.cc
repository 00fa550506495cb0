#include "apps/terrain_parameters.h"

#include "apps/choice.h"
#include "apps/number_list.h"
#include "fem/sole_parameters.h"

#include <cmath>
#include <cstdint>
#include <sstream>
#include <stdexcept>
#include <string>

namespace plantar::app {

using dealii::Patterns::Anything;
using dealii::Patterns::Double;
using dealii::Patterns::Integer;

namespace {

ChoiceTable<contact::TerrainType> terrain_types() {
  ChoiceTable<contact::TerrainType> table;
  for (const auto& [type, name] : contact::terrain_type_names())
    table.emplace_back(type, name);
  return table;
}

void require(bool ok, const std::string& name, double value, const std::string& range) {
  if (!ok) {
    std::ostringstream msg;
    msg << "Terrain/" << name << " = " << value << ": must be " << range;
    throw std::invalid_argument(msg.str());
  }
}

} // namespace

const char* to_string(contact::TerrainType type) {
  return choice_name(terrain_types(), type);
}

void TerrainSceneParameters::declare(dealii::ParameterHandler& prm) {
  const contact::TerrainParameters d;
  prm.declare_entry("Type", to_string(d.type), choice_pattern(terrain_types()),
                    "The ground (docs/terrain.md): flat (z = Level), slope (a plane turned about "
                    "a horizontal axis), steps (a step edge), bumps (sinusoidal), cylinder (a "
                    "cylindrical bump), rough (a random Gaussian-correlated surface), grid "
                    "(heights from a CSV file). The robot starts on it: its reference is raised "
                    "by the highest ground under its contact points at t = 0.");
  prm.declare_entry("Level", number_text(d.level), Double(),
                    "z0 (m): the flat ground's height; the base of the other types.");
  prm.declare_entry("Origin x", number_text(d.origin_x), Double(),
                    "x (m) of the slope's pivot, the step edge, the cylinder axis, the rough "
                    "surface's centre, the grid's first value.");
  prm.declare_entry("Origin y", number_text(d.origin_y), Double(), "y (m) of the same point.");
  prm.declare_entry("Slope angle", number_text(d.slope_angle), Double(-89.9, 89.9),
                    "slope: rotation (deg) of the ground about the slope axis (right hand), "
                    "(-90, 90).");
  prm.declare_entry("Slope axis heading", number_text(d.slope_axis_heading), Double(),
                    "slope: the axis' angle from x (deg); 90 (the axis along y) with a positive "
                    "angle: the ground falls towards +x.");
  prm.declare_entry("Step height", number_text(d.step_height), Double(),
                    "steps: rise (m) of the upper level above Level (negative: a step down).");
  prm.declare_entry("Step heading", number_text(d.step_heading), Double(),
                    "steps: direction (deg from x) of the upper side; the edge passes through "
                    "Origin.");
  prm.declare_entry("Step width", number_text(d.step_width), Double(0),
                    "steps: horizontal width (m) of the C1 ramp over the edge, >= 0; 0: a sharp "
                    "edge (the riser is not a contact surface; docs/terrain.md).");
  prm.declare_entry("Bump amplitude", number_text(d.bump_amplitude), Double(),
                    "bumps: A (m) of h = Level + A cos(2 pi x / Lx) cos(2 pi y / Ly).");
  prm.declare_entry("Bump wavelength x", number_text(d.bump_wavelength_x), Double(0),
                    "bumps: Lx (m), > 0, or 0: no variation along x.");
  prm.declare_entry("Bump wavelength y", number_text(d.bump_wavelength_y), Double(0),
                    "bumps: Ly (m), > 0, or 0: no variation along y.");
  prm.declare_entry("Cylinder radius", number_text(d.cylinder_radius), Double(0),
                    "cylinder: radius R (m), > 0.");
  prm.declare_entry("Cylinder height", number_text(d.cylinder_height), Double(0),
                    "cylinder: rise b (m) of the bump above Level, (0, R].");
  prm.declare_entry("Cylinder heading", number_text(d.cylinder_heading), Double(),
                    "cylinder: the axis' angle from x (deg); it passes through Origin.");
  prm.declare_entry("Rough RMS", number_text(d.rough.rms), Double(0, 1),
                    "rough: RMS height sigma (m), [0, 1].");
  prm.declare_entry("Rough correlation length", number_text(d.rough.correlation_length),
                    Double(0, 100),
                    "rough: l (m), the lag at which the correlation exp(-r^2/l^2) falls to 1/e, "
                    "(0, 100].");
  prm.declare_entry("Rough seed", std::to_string(d.rough.seed), Integer(0),
                    "rough: seed of the random modes (the same surface for the same seed).");
  prm.declare_entry("Rough modes", std::to_string(d.rough.modes), Integer(1, 100000),
                    "rough: number of random Fourier modes N, [1, 100000].");
  prm.declare_entry("Rough size", number_text(d.rough.size_x) + ", " + number_text(d.rough.size_y),
                    Anything(),
                    "rough: 'Lx, Ly' (m): the sampled area, centred on Origin (outside it the "
                    "height is continued from its border), each in (0, 1000].");
  prm.declare_entry("Grid file", d.grid_file, Anything(),
                    "grid: CSV of heights (m), one row per y, one column per x, '#' comments "
                    "(docs/terrain.md); relative paths: the scene directory, then the Plantar "
                    "tree.");
  prm.declare_entry("Grid spacing", number_text(d.grid_spacing), Double(0),
                    "grid: spacing (m) of the rows and columns, > 0.");
}

void TerrainSceneParameters::parse(dealii::ParameterHandler& prm,
                                   const std::filesystem::path& scene_directory) {
  contact::TerrainParameters& t = terrain;
  t.type = parse_choice(terrain_types(), prm.get("Type"), "Terrain/Type");
  t.level = prm.get_double("Level");
  t.origin_x = prm.get_double("Origin x");
  t.origin_y = prm.get_double("Origin y");
  t.slope_angle = prm.get_double("Slope angle");
  t.slope_axis_heading = prm.get_double("Slope axis heading");
  t.step_height = prm.get_double("Step height");
  t.step_heading = prm.get_double("Step heading");
  t.step_width = prm.get_double("Step width");
  t.bump_amplitude = prm.get_double("Bump amplitude");
  t.bump_wavelength_x = prm.get_double("Bump wavelength x");
  t.bump_wavelength_y = prm.get_double("Bump wavelength y");
  t.cylinder_radius = prm.get_double("Cylinder radius");
  t.cylinder_height = prm.get_double("Cylinder height");
  t.cylinder_heading = prm.get_double("Cylinder heading");
  t.rough.rms = prm.get_double("Rough RMS");
  t.rough.correlation_length = prm.get_double("Rough correlation length");
  t.rough.seed = static_cast<std::uint64_t>(prm.get_integer("Rough seed"));
  t.rough.modes = prm.get_integer("Rough modes");
  const std::vector<double> size = parse_numbers(prm.get("Rough size"), "Terrain/Rough size", 2, 2);
  t.rough.size_x = size[0];
  t.rough.size_y = size[1];
  t.grid_spacing = prm.get_double("Grid spacing");
  const std::string grid = prm.get("Grid file");
  t.grid_file = grid.empty() ? std::string() : fem::resolve_path(grid, scene_directory).string();
  require(std::abs(t.slope_angle) < 90, "Slope angle", t.slope_angle, "in (-90, 90) deg");
  require(t.cylinder_radius > 0, "Cylinder radius", t.cylinder_radius, "> 0");
  require(t.cylinder_height > 0 && t.cylinder_height <= t.cylinder_radius, "Cylinder height",
          t.cylinder_height, "in (0, Cylinder radius]");
  require(t.rough.correlation_length > 0, "Rough correlation length", t.rough.correlation_length,
          "in (0, 100] m");
  require(size[0] > 0 && size[0] <= 1000 && size[1] > 0 && size[1] <= 1000, "Rough size",
          size[0] > 0 && size[0] <= 1000 ? size[1] : size[0], "in (0, 1000] m each");
  require(t.grid_spacing > 0, "Grid spacing", t.grid_spacing, "> 0");
  if (t.type == contact::TerrainType::grid && t.grid_file.empty())
    throw std::invalid_argument("Terrain/Grid file is empty: Terrain/Type = grid needs a CSV file");
  if (t.type == contact::TerrainType::grid && !std::filesystem::exists(t.grid_file))
    throw std::invalid_argument("Terrain/Grid file = " + grid + ": no such file (" + t.grid_file +
                                ")");
}

} // namespace plantar::app
