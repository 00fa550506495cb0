#include "apps/static_contact_parameters.h"

#include "apps/choice.h"
#include "apps/number_list.h"

#include <cmath>
#include <sstream>
#include <stdexcept>

namespace plantar::app {

using dealii::Patterns::Anything;
using dealii::Patterns::Double;
using dealii::Patterns::Integer;
using dealii::Patterns::Selection;

namespace {

const ChoiceTable<FootControl> controls{{FootControl::displacement, "displacement"},
                                        {FootControl::force, "force"}};

std::string triple_text(const std::array<double, 3>& values) {
  return number_text(values[0]) + ", " + number_text(values[1]) + ", " + number_text(values[2]);
}

std::array<double, 3> parse_triple(dealii::ParameterHandler& prm, const std::string& name,
                                   double bound) {
  const std::string parameter = "Static contact/" + name;
  const auto values = parse_numbers(prm.get(name), parameter, 3, 3);
  for (const double value : values)
    if (std::abs(value) > bound) {
      std::ostringstream msg;
      msg << parameter << " = " << prm.get(name) << ": each component must be in [" << -bound
          << ", " << bound << "]";
      throw std::invalid_argument(msg.str());
    }
  return {values[0], values[1], values[2]};
}

} // namespace

void StaticContactParameters::declare(dealii::ParameterHandler& prm) {
  const StaticContactParameters d;
  prm.declare_entry("Control", "displacement", choice_pattern(controls),
                    "displacement: the foot's rigid displacement is Foot translation and Foot "
                    "rotation; force: the foot carries Normal force and Moment x, y (about the "
                    "Rotation point), its vertical translation and x, y rotations are solved for "
                    "(starting from Foot translation z and Foot rotation x, y; the other "
                    "components are kept).");
  prm.declare_entry("Normal force", number_text(d.normal_force), Double(0, 1e5),
                    "Control = force: the foot presses the sole down with this force (N), "
                    "(0, 1e5].");
  prm.declare_entry("Moment x", number_text(d.moment_x), Double(-1e4, 1e4),
                    "Control = force: moment (N m) of the foot on the sole about the rotation "
                    "point, x component, [-1e4, 1e4].");
  prm.declare_entry("Moment y", number_text(d.moment_y), Double(-1e4, 1e4),
                    "Control = force: moment (N m), y component, [-1e4, 1e4].");
  prm.declare_entry("Load tolerance", number_text(d.load_tolerance), Double(0, 1e-2),
                    "Control = force: stop when |F_z + N| <= this N and |M - M*| <= this N L "
                    "(L: largest distance from the rotation point to a contact node), (0, 1e-2].");
  prm.declare_entry("Foot translation", triple_text(d.translation), Anything(),
                    "x, y, z of the rigid foot's translation (m), each in [-0.05, 0.05]; the "
                    "sole's top face moves with the foot (negative z presses it down).");
  prm.declare_entry("Foot rotation", triple_text(d.rotation), Anything(),
                    "Rotation vector of the foot (rad), each in [-0.2, 0.2], linearised: "
                    "u = t + theta x (x - p).");
  prm.declare_entry("Rotation point", triple_text(d.rotation_point), Anything(),
                    "The rotation's point p (m) from the centre of the sole's top face, each in "
                    "[-1, 1].");
  prm.declare_entry("Initial offset", number_text(d.initial_offset), Double(0, 0.1),
                    "Distance (m) from the unloaded sole's bottom down to the ground z, [0, 0.1].");
  prm.declare_entry("Friction coefficient", number_text(d.friction), Double(0, 10),
                    "Coulomb's mu between sole and ground, [0, 10].");
  prm.declare_entry("Refinements", std::to_string(d.refinements), Integer(0, 8),
                    "Global refinements of the gmsh mesh (Sole/Cell kind = hexahedron), [0, 8]; "
                    "each multiplies the dofs by about 8.");
  prm.declare_entry("Tolerance", number_text(d.tolerance), Double(0, 1e-2),
                    "Stop when the nodal complementarity residual is below this fraction of the "
                    "largest nodal contact force, (0, 1e-2].");
  prm.declare_entry("Maximum iterations", std::to_string(d.max_iterations), Integer(1, 1000),
                    "Semismooth Newton iterations before the solve is reported failed, [1, 1000].");
  prm.declare_entry("Linear solver", "mumps", Selection("mumps|gmres amg|gmres gamg"),
                    "Each Newton system: mumps (sparse direct, PETSc), gmres amg (GMRES + "
                    "BoomerAMG on the Newton increment) or gmres gamg (GMRES + PETSc's GAMG "
                    "with the rigid-body modes, memory linear in the DoF); "
                    "docs/static_contact.md compares them.");
}

void StaticContactParameters::parse(dealii::ParameterHandler& prm) {
  control = parse_choice(controls, prm.get("Control"), "Static contact/Control");
  translation = parse_triple(prm, "Foot translation", 0.05);
  rotation = parse_triple(prm, "Foot rotation", 0.2);
  rotation_point = parse_triple(prm, "Rotation point", 1.0);
  initial_offset = prm.get_double("Initial offset");
  friction = prm.get_double("Friction coefficient");
  refinements = prm.get_integer("Refinements");
  tolerance = prm.get_double("Tolerance");
  max_iterations = prm.get_integer("Maximum iterations");
  normal_force = prm.get_double("Normal force");
  moment_x = prm.get_double("Moment x");
  moment_y = prm.get_double("Moment y");
  load_tolerance = prm.get_double("Load tolerance");
  const auto positive = [](double value, const char* name, const char* range) {
    if (!(value > 0)) {
      std::ostringstream msg;
      msg << "Static contact/" << name << " = " << value << ": must be in " << range;
      throw std::invalid_argument(msg.str());
    }
  };
  positive(normal_force, "Normal force", "(0, 1e5] N");
  positive(load_tolerance, "Load tolerance", "(0, 1e-2]");
  positive(tolerance, "Tolerance", "(0, 1e-2]");
  linear_solver =
      fem::parse_contact_linear_solver(prm.get("Linear solver"), "Static contact/Linear solver");
}

} // namespace plantar::app
