#include "apps/pad_parameters.h"

#include "apps/number_list.h"
#include "fem/material_table.h"
#include "fem/sole_parameters.h"

#include <deal.II/base/utilities.h>

#include <map>
#include <optional>
#include <sstream>
#include <stdexcept>

namespace plantar::app {

using dealii::Patterns::Anything;
using dealii::Patterns::Double;
using dealii::Patterns::Integer;

namespace {

std::string slot_name(int slot) {
  return "Pad " + std::to_string(slot + 1);
}

/// "NAME = VALUE, NAME = VALUE" -> gmsh -setnumber overrides.
std::map<std::string, double> parse_mesh_numbers(const std::string& text,
                                                 const std::string& parameter) {
  std::map<std::string, double> numbers;
  for (const std::string& item : dealii::Utilities::split_string_list(text, ',')) {
    const auto equal = item.find('=');
    std::string name = equal == std::string::npos ? "" : item.substr(0, equal);
    name.erase(name.find_last_not_of(" \t") + 1);
    const std::optional<double> value =
        equal == std::string::npos ? std::nullopt : to_number(item.substr(equal + 1));
    if (name.empty() || !value)
      throw std::invalid_argument(parameter + " = '" + text + "': '" + item +
                                  "' is not 'NAME = finite number'");
    numbers[name] = *value;
  }
  return numbers;
}

} // namespace

void PadParameters::declare(dealii::ParameterHandler& prm) {
  const PadEntry d;
  for (int slot = 0; slot < max_pads; ++slot) {
    prm.enter_subsection(slot_name(slot));
    prm.declare_entry("Link", "", Anything(),
                      "Link carrying the pad (a link of Robot/URDF file); empty: no pad.");
    prm.declare_entry("Name", "", Anything(),
                      "Name in outputs (CSV columns, .vtu files): letters, digits, '_', '-'; "
                      "empty: pad_<slot>.");
    prm.declare_entry("Geometry file", d.description.geometry_file.string(), Anything(),
                      "gmsh .geo of the pad: physical surfaces 'top' (fixed on the link) and "
                      "'bottom' (contact), one physical volume per material region; relative "
                      "paths: the scene's directory, then the Plantar tree.");
    prm.declare_entry("Mesh numbers", "", Anything(),
                      "gmsh -setnumber overrides, 'NAME = VALUE, ...' (e.g. PadThickness = "
                      "0.02, PadMeshSize = 0.008 for meshes/pad_knee.geo).");
    prm.declare_entry("Materials", d.description.materials, Anything(),
                      "Materials by physical volume, 'region: E=..., nu=...; ...' (E in Pa), "
                      "as Sole/Materials; law=prony in a region makes the pad viscoelastic "
                      "(Prony series, condensed at Simulation/Time step).");
    prm.declare_entry("Degree", std::to_string(d.description.degree), Integer(1, 2),
                      "Lagrange degree of the pad's elements, 1 or 2.");
    prm.declare_entry("Placement", "0, 0, 0", Anything(),
                      "Pad frame in the link frame, 'x, y, z' or 'x, y, z, roll, pitch, yaw' (m, "
                      "rad; URDF rpy). The pad frame has its origin at the centre of the top "
                      "face, the pad below it (z <= 0).");
    prm.declare_entry("Friction", number_text(d.description.friction), Double(0, 100),
                      "Coulomb mu between the pad and the ground, [0, 100].");
    prm.declare_entry("Damping time", number_text(d.damping_time), Double(0),
                      "Kelvin-Voigt beta (s), D = beta K; 0: elastic. Elastic pads only (a "
                      "viscoelastic pad dissipates through its Prony branches).");
    prm.declare_entry("Max compression", number_text(d.max_compression), Double(0, 1),
                      "The run fails when a node is compressed by more than this fraction of "
                      "the pad's thickness, (0, 1].");
    prm.leave_subsection();
  }
}

void PadParameters::parse(dealii::ParameterHandler& prm,
                          const std::filesystem::path& scene_directory) {
  pads.clear();
  for (int slot = 0; slot < max_pads; ++slot) {
    const std::string section = slot_name(slot);
    prm.enter_subsection(section);
    PadEntry entry;
    coupling::PadDescription& pad = entry.description;
    pad.link = prm.get("Link");
    if (pad.link.empty()) {
      prm.leave_subsection();
      continue;
    }
    pad.name = prm.get("Name");
    if (pad.name.empty())
      pad.name = "pad_" + std::to_string(slot + 1);
    // The name becomes CSV column names and file names.
    if (pad.name.find_first_not_of("abcdefghijklmnopqrstuvwxyzABCDEFGHIJKLMNOPQRSTUVWXYZ"
                                   "0123456789_-") != std::string::npos)
      throw std::invalid_argument(section + "/Name = '" + pad.name +
                                  "': allowed characters are letters, digits, '_' and '-'");
    pad.geometry_file = fem::resolve_path(prm.get("Geometry file"), scene_directory);
    pad.mesh_numbers = parse_mesh_numbers(prm.get("Mesh numbers"), section + "/Mesh numbers");
    pad.materials = prm.get("Materials");
    pad.degree = static_cast<unsigned int>(prm.get_integer("Degree"));
    const std::vector<double> placement =
        parse_numbers(prm.get("Placement"), section + "/Placement", 3, 6);
    if (placement.size() != 3 && placement.size() != 6)
      throw std::invalid_argument(section + "/Placement = '" + prm.get("Placement") +
                                  "': expected 'x, y, z' or 'x, y, z, roll, pitch, yaw'");
    pad.translation << placement[0], placement[1], placement[2];
    if (placement.size() == 6)
      pad.rpy << placement[3], placement[4], placement[5];
    pad.friction = prm.get_double("Friction");
    entry.damping_time = prm.get_double("Damping time");
    entry.max_compression = prm.get_double("Max compression");
    prm.leave_subsection();
    bool viscoelastic = false;
    for (const auto& [region, spec] :
         fem::parse_material_specs(pad.materials, section + "/Materials"))
      viscoelastic = viscoelastic || spec.law == "prony";
    if (viscoelastic && entry.damping_time != 0.0)
      throw std::invalid_argument(
          section + "/Damping time = " + number_text(entry.damping_time) +
          " s: a viscoelastic pad (law=prony in " + section +
          "/Materials) dissipates through its Prony branches, allowed 0 (no Kelvin-Voigt "
          "damping on top)");
    if (!(entry.max_compression > 0))
      throw std::invalid_argument(section + "/Max compression = " +
                                  number_text(entry.max_compression) + ": must be in (0, 1]");
    try {
      pad.validate();
    } catch (const std::invalid_argument& e) {
      throw std::invalid_argument(section + ": " + e.what());
    }
    for (const PadEntry& other : pads)
      if (other.description.name == pad.name)
        throw std::invalid_argument(section + "/Name = '" + pad.name +
                                    "': another pad has this name");
    pads.push_back(std::move(entry));
  }
}

} // namespace plantar::app
