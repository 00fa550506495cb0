#include "apps/scene.h"

#include "fem/exception_text.h"

#include <stdexcept>

namespace plantar::app {

using dealii::Patterns::Bool;
using dealii::Patterns::Double;
using dealii::Patterns::Selection;

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
  prm.declare_entry("VTK stick radius", "0.02", dealii::Patterns::Double(0.001, 0.2),
                    "Humanoid scenes: radius (m) of the cylinders drawn for links without URDF "
                    "<visual> or <collision> boxes or cylinders.");
  prm.declare_entry("Write CSV", "true", Bool(),
                    "Humanoid scenes: write waist.csv, joints.csv and contacts.csv.");
  prm.declare_entry("Output every", "1", dealii::Patterns::Integer(1),
                    "Humanoid scenes: one CSV row every this many time steps.");
}

void OutputParameters::parse(dealii::ParameterHandler& prm) {
  write_vtu = prm.get_bool("Write VTU");
  write_csv = prm.get_bool("Write CSV");
  output_every = prm.get_integer("Output every");
  vtk_every = prm.get_integer("VTK every");
  vtk_stick_radius = prm.get_double("VTK stick radius");
}

void Scene::declare(dealii::ParameterHandler& prm) {
  prm.declare_entry("Scene type", "static sole", Selection("static sole|stand|drop|lean|walk"),
                    "static sole: the sole under a uniform ground reaction (Static load); "
                    "stand: the robot standing still (bent knees) for Simulation/Duration; "
                    "drop: straight legs, released Simulation/Release height above the ground; "
                    "lean: waist roll ramped to Lean/Final angle; walk: the walk of subsection "
                    "Walking (ZMP preview control, PD joint tracking). The humanoid scenes use "
                    "Robot, Contact, Control, Simulation (and Sole for Robot/Foot form = fem "
                    "sole, or for the outline of the rigid sole).");
  prm.enter_subsection("Sole");
  fem::SoleParameters::declare(prm);
  SoleReductionParameters::declare(prm);
  prm.leave_subsection();
  prm.enter_subsection("Static load");
  StaticLoadParameters::declare(prm);
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
  prm.enter_subsection("Output");
  OutputParameters::declare(prm);
  prm.leave_subsection();
  prm.enter_subsection("Sweep");
  SweepParameters::declare(prm);
  prm.leave_subsection();
}

void Scene::parse(dealii::ParameterHandler& prm, const std::filesystem::path& scene_directory) {
  type = prm.get("Scene type");
  prm.enter_subsection("Sole");
  sole.parse(prm, scene_directory);
  sole_reduction.parse(prm);
  prm.leave_subsection();
  prm.enter_subsection("Static load");
  static_load.parse(prm);
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
  prm.enter_subsection("Output");
  output.parse(prm);
  prm.leave_subsection();
  prm.enter_subsection("Sweep");
  sweep.parse(prm);
  prm.leave_subsection();
}

Scene load_scene(const std::filesystem::path& file, dealii::ParameterHandler& prm) {
  if (!std::filesystem::exists(file))
    throw std::runtime_error("scene '" + file.string() + "': no such file");
  Scene::declare(prm);
  try {
    prm.parse_input(file.string(), "", false, true);
  } catch (const std::exception& e) {
    throw std::runtime_error("scene '" + file.string() + "': " + fem::exception_text(e));
  }
  Scene scene;
  try {
    scene.parse(prm, std::filesystem::absolute(file).parent_path());
  } catch (const std::exception& e) {
    throw std::runtime_error("scene '" + file.string() + "': " + fem::exception_text(e));
  }
  return scene;
}

} // namespace plantar::app
