#include "apps/scene.h"

#include "apps/choice.h"
#include "apps/number_list.h"
#include "fem/exception_text.h"

#include <fstream>
#include <sstream>
#include <stdexcept>

namespace plantar::app {

using dealii::Patterns::Bool;
using dealii::Patterns::Double;
using dealii::Patterns::Selection;

namespace {
const ChoiceTable<SceneType> scene_types{{SceneType::static_sole, "static sole"},
                                         {SceneType::static_contact, "static contact"},
                                         {SceneType::stand, "stand"},
                                         {SceneType::drop, "drop"},
                                         {SceneType::lean, "lean"},
                                         {SceneType::walk, "walk"}};
} // namespace

const char* to_string(SceneType type) {
  return choice_name(scene_types, type);
}

void StaticLoadParameters::declare(dealii::ParameterHandler& prm) {
  prm.declare_entry("Total normal force", "600", Double(),
                    "Ground reaction on the bottom face along +z (N), spread uniformly.");
  prm.declare_entry("Total tangential force x", "0", Double(),
                    "Tangential ground reaction along x (N), spread uniformly.");
  prm.declare_entry("Total tangential force y", "0", Double(),
                    "Tangential ground reaction along y (N), spread uniformly.");
}

void StaticLoadParameters::parse(dealii::ParameterHandler& prm) {
  normal_force = prm.get_double("Total normal force");
  tangential_x = prm.get_double("Total tangential force x");
  tangential_y = prm.get_double("Total tangential force y");
}

void OutputParameters::declare(dealii::ParameterHandler& prm) {
  prm.declare_entry("Write VTU", "true", Bool(),
                    "static sole: write the sole's fields as sole.vtu; humanoid scenes: write "
                    "the ParaView series (scene.pvd, vtk/*.vtu; docs/paraview.md).");
  prm.declare_entry("VTK every", "40", dealii::Patterns::Integer(1),
                    "Humanoid scenes: one ParaView frame every this many time steps (and the "
                    "first and last steps).");
  prm.declare_entry("VTK collection every", "25", dealii::Patterns::Integer(1),
                    "Humanoid scenes: rewrite the .pvd collections (scene.pvd, links.pvd, ...) "
                    "every this many ParaView frames, and after the last frame (also when a run "
                    "fails). Each rewrite replaces the files (write, then rename), which costs "
                    "about 1.5 ms per file on ext4 (docs/performance.md, the rigid robot against "
                    "MuJoCo): 25 rewrites once per simulated second at VTK every = 40, dt = 1 ms; "
                    "1 rewrites them at every frame (a live view of a long run).");
  prm.declare_entry("VTK stick radius", "0.02", dealii::Patterns::Double(0.001, 0.2),
                    "Humanoid scenes: radius (m) of the cylinders drawn for links without URDF "
                    "<visual> or <collision> boxes or cylinders.");
  prm.declare_entry("Write CSV", "true", Bool(),
                    "Humanoid scenes: write waist.csv, joints.csv and contacts.csv.");
  prm.declare_entry("Output every", "1", dealii::Patterns::Integer(1),
                    "Humanoid scenes: one CSV row every this many time steps.");
  const OutputParameters d;
  prm.declare_entry("Accelerometer bandwidth", number_text(d.accelerometer_bandwidth),
                    Double(0, 1e4),
                    "Humanoid scenes: cut-off (Hz) of the waist accelerometer, a second-order "
                    "Butterworth low-pass of the raw a_z, [0, 1e4]; 0, or at or above the "
                    "Nyquist frequency 1 / (2 Simulation/Time step): raw. waist.csv keeps the "
                    "raw a_z (docs/walking.md).");
  prm.declare_entry("Landing threshold", number_text(d.landing_threshold), Double(0, 1),
                    "Humanoid scenes: a foot lands when its vertical force rises through this "
                    "fraction of the robot's weight, (0, 1) (landings.csv).");
  prm.declare_entry("Landing window", number_text(d.landing_window), Double(0, 1),
                    "Humanoid scenes: the landing figures (impulse, peak force, rise time, "
                    "peak filtered a_z) cover this time after touchdown (s), (0, 1].");
}

void OutputParameters::parse(dealii::ParameterHandler& prm) {
  write_vtu = prm.get_bool("Write VTU");
  write_csv = prm.get_bool("Write CSV");
  output_every = prm.get_integer("Output every");
  vtk_every = prm.get_integer("VTK every");
  vtk_collection_every = prm.get_integer("VTK collection every");
  vtk_stick_radius = prm.get_double("VTK stick radius");
  accelerometer_bandwidth = prm.get_double("Accelerometer bandwidth");
  landing_threshold = prm.get_double("Landing threshold");
  landing_window = prm.get_double("Landing window");
  const auto require = [](bool ok, const char* name, double value, const char* range) {
    if (!ok) {
      std::ostringstream msg;
      msg << "Output/" << name << " = " << value << ": must be in " << range;
      throw std::invalid_argument(msg.str());
    }
  };
  require(landing_threshold > 0 && landing_threshold < 1, "Landing threshold", landing_threshold,
          "(0, 1)");
  require(landing_window > 0 && landing_window <= 1, "Landing window", landing_window, "(0, 1] s");
}

void Scene::declare(dealii::ParameterHandler& prm) {
  prm.declare_entry(
      "Scene type", to_string(Scene().type), choice_pattern(scene_types),
      "static sole: the sole under a uniform ground reaction (Static load); "
      "static contact: the sole (hexahedra) under a rigid foot pressed onto the ground with "
      "Coulomb friction (Static contact), on distributed PETSc (mpirun -np N plantar run); "
      "stand: the robot standing still (bent knees) for Simulation/Duration; "
      "drop: straight legs (or Simulation/Drop posture), released with the lowest contact "
      "point Simulation/Release height above the ground; "
      "lean: waist roll ramped to Lean/Final angle; walk: the walk of subsection "
      "Walking (ZMP preview control, PD joint tracking). The humanoid scenes use "
      "Robot, Contact, Control, Simulation (and Sole for Robot/Foot form = fem "
      "sole, or for the outline of the rigid sole).");
  prm.enter_subsection("Sole");
  fem::SoleParameters::declare(prm);
  SoleReductionParameters::declare(prm);
  SoleValidityParameters::declare(prm);
  prm.leave_subsection();
  prm.enter_subsection("Static load");
  StaticLoadParameters::declare(prm);
  prm.leave_subsection();
  prm.enter_subsection("Static contact");
  StaticContactParameters::declare(prm);
  prm.leave_subsection();
  prm.enter_subsection("Robot");
  RobotParameters::declare(prm);
  prm.leave_subsection();
  prm.enter_subsection("Contact");
  ContactParameters::declare(prm);
  prm.leave_subsection();
  prm.enter_subsection("Control");
  ControlParameters::declare(prm);
  prm.leave_subsection();
  prm.enter_subsection("Walking");
  WalkingSceneParameters::declare(prm);
  prm.leave_subsection();
  prm.enter_subsection("Lean");
  LeanSceneParameters::declare(prm);
  prm.leave_subsection();
  prm.enter_subsection("Simulation");
  SimulationParameters::declare(prm);
  prm.leave_subsection();
  PadParameters::declare(prm);
  prm.enter_subsection("Terrain");
  TerrainSceneParameters::declare(prm);
  prm.leave_subsection();
  prm.enter_subsection("Output");
  OutputParameters::declare(prm);
  prm.leave_subsection();
  prm.enter_subsection("Sweep");
  SweepParameters::declare(prm);
  prm.leave_subsection();
}

void Scene::parse(dealii::ParameterHandler& prm, const std::filesystem::path& scene_directory) {
  type = parse_choice(scene_types, prm.get("Scene type"), "Scene type");
  prm.enter_subsection("Sole");
  sole.parse(prm, scene_directory);
  sole_reduction.parse(prm);
  sole_validity.parse(prm);
  prm.leave_subsection();
  prm.enter_subsection("Static load");
  static_load.parse(prm);
  prm.leave_subsection();
  prm.enter_subsection("Static contact");
  static_contact.parse(prm);
  prm.leave_subsection();
  prm.enter_subsection("Robot");
  robot.parse(prm, scene_directory);
  prm.leave_subsection();
  prm.enter_subsection("Contact");
  contact.parse(prm);
  prm.leave_subsection();
  prm.enter_subsection("Control");
  control.parse(prm);
  prm.leave_subsection();
  prm.enter_subsection("Walking");
  walking.parse(prm);
  prm.leave_subsection();
  prm.enter_subsection("Lean");
  lean.parse(prm);
  prm.leave_subsection();
  prm.enter_subsection("Simulation");
  simulation.parse(prm);
  prm.leave_subsection();
  pads.parse(prm, scene_directory);
  prm.enter_subsection("Terrain");
  terrain.parse(prm, scene_directory);
  prm.leave_subsection();
  prm.enter_subsection("Output");
  output.parse(prm);
  prm.leave_subsection();
  prm.enter_subsection("Sweep");
  sweep.parse(prm);
  prm.leave_subsection();
  sweep.check_axes(prm);
}

namespace {

/// Parses @p file into @p prm; each top-level line 'include PATH' parses PATH there (resolved
/// from @p file's directory, then the Plantar tree), recursively. Pieces between includes are
/// padded with empty lines so that deal.II's messages give the file's own line numbers.
void parse_with_includes(const std::filesystem::path& file, dealii::ParameterHandler& prm,
                         int depth) {
  if (depth > 8)
    throw std::runtime_error("include " + file.string() + ": more than 8 levels (a cycle?)");
  const std::filesystem::path directory = std::filesystem::absolute(file).parent_path();
  std::ifstream in(file);
  if (!in)
    throw std::runtime_error("cannot read '" + file.string() + "'");
  std::string piece;
  int piece_start = 1, line_number = 0;
  const auto parse_piece = [&] {
    std::istringstream stream(std::string(piece_start - 1, '\n') + piece);
    prm.parse_input(stream, file.string(), "", false);
    piece.clear();
  };
  for (std::string line; std::getline(in, line);) {
    ++line_number;
    const auto first = line.find_first_not_of(" \t");
    if (first == std::string::npos || line.compare(first, 8, "include ") != 0) {
      piece += line + "\n";
      continue;
    }
    std::string path = line.substr(first + 8);
    path.erase(0, path.find_first_not_of(" \t"));
    path.erase(path.find_last_not_of(" \t\r") + 1);
    const std::filesystem::path resolved = fem::resolve_path(path, directory);
    if (!std::filesystem::is_regular_file(resolved))
      throw std::runtime_error("line " + std::to_string(line_number) + " of " + file.string() +
                               ": include " + path + ": no such file (looked in '" +
                               directory.string() + "' and the Plantar source tree)");
    parse_piece();
    parse_with_includes(resolved, prm, depth + 1);
    piece_start = line_number + 1;
  }
  parse_piece();
}

} // namespace

void read_scene_file(const std::filesystem::path& file, dealii::ParameterHandler& prm) {
  if (!std::filesystem::exists(file))
    throw std::runtime_error("scene '" + file.string() + "': no such file");
  Scene::declare(prm);
  try {
    parse_with_includes(file, prm, 0);
  } catch (const std::exception& e) {
    throw std::runtime_error("scene '" + file.string() + "': " + fem::exception_text(e));
  }
}

Scene load_scene(const std::filesystem::path& file, dealii::ParameterHandler& prm) {
  read_scene_file(file, prm);
  Scene scene;
  try {
    scene.parse(prm, std::filesystem::absolute(file).parent_path());
  } catch (const std::exception& e) {
    throw std::runtime_error("scene '" + file.string() + "': " + fem::exception_text(e));
  }
  return scene;
}

} // namespace plantar::app
