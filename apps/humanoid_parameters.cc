#include "apps/humanoid_parameters.h"

#include "apps/choice.h"
#include "apps/contact_solver_name.h"
#include "apps/number_list.h"
#include "fem/sole_parameters.h"

#include <Eigen/Geometry>

#include <cmath>
#include <cstdint>
#include <optional>
#include <sstream>
#include <stdexcept>

namespace plantar::app {

using dealii::Patterns::Anything;
using dealii::Patterns::Bool;
using dealii::Patterns::Double;
using dealii::Patterns::Integer;
using dealii::Patterns::Selection;

namespace {

/// Throws std::invalid_argument "<name> = <value>: must be <range>" unless @p ok.
void require(bool ok, const std::string& name, double value, const std::string& range) {
  if (!ok) {
    std::ostringstream msg;
    msg << name << " = " << value << ": must be " << range;
    throw std::invalid_argument(msg.str());
  }
}

std::string footsteps_text(const std::vector<walking::Footstep>& steps) {
  std::ostringstream out;
  for (std::size_t i = 0; i < steps.size(); ++i)
    out << (i ? "; " : "") << steps[i].x << ", " << steps[i].y << ", " << steps[i].yaw;
  return out.str();
}

/// 'x, y, z' or 'x, y, z, roll, pitch, yaw' (m, rad; URDF rpy: R = Rz(yaw) Ry(pitch) Rx(roll)).
multibody::SE3 parse_placement(const std::string& text, const std::string& parameter) {
  const std::vector<double> v = parse_numbers(text, parameter, 3, 6);
  if (v.size() != 3 && v.size() != 6)
    throw std::invalid_argument(parameter + " = '" + text +
                                "': expected 'x, y, z' or 'x, y, z, roll, pitch, yaw'");
  Eigen::Matrix3d rotation = Eigen::Matrix3d::Identity();
  if (v.size() == 6)
    rotation = (Eigen::AngleAxisd(v[5], Eigen::Vector3d::UnitZ()) *
                Eigen::AngleAxisd(v[4], Eigen::Vector3d::UnitY()) *
                Eigen::AngleAxisd(v[3], Eigen::Vector3d::UnitX()))
                   .toRotationMatrix();
  return multibody::SE3(rotation, Eigen::Vector3d(v[0], v[1], v[2]));
}

/// 'joint: degrees, joint: degrees, ...' -> (joint, radians); prismatic joints in metres.
std::vector<std::pair<std::string, double>> parse_posture(const std::string& text,
                                                          const std::string& parameter) {
  std::vector<std::pair<std::string, double>> posture;
  for (const std::string& item : dealii::Utilities::split_string_list(text, ',')) {
    const auto colon = item.find(':');
    const std::vector<double> value = colon == std::string::npos
                                          ? std::vector<double>{}
                                          : parse_numbers(item.substr(colon + 1), parameter, 1, 1);
    std::string name = colon == std::string::npos ? "" : item.substr(0, colon);
    name.erase(name.find_last_not_of(" \t") + 1);
    if (name.empty())
      throw std::invalid_argument(parameter + ": '" + item + "' is not 'joint: angle'");
    posture.emplace_back(name, value[0] * (M_PI / 180.0));
  }
  return posture;
}

walking::Footstep parse_one(const std::string& text, const std::string& parameter) {
  const auto steps = parse_footsteps(text, parameter);
  if (steps.size() != 1)
    throw std::invalid_argument(parameter + " = '" + text + "': expected one 'x, y, yaw'");
  return steps[0];
}

/// Contact/Failure residual: a residual (m/s, > 0) or 'k x Tolerance' (k >= 1).
double parse_failure_residual(const std::string& text, double tolerance) {
  const std::string error = "Contact/Failure residual = '" + text +
                            "': allowed a residual in m/s (> 0) or 'k x Tolerance' (k >= 1)";
  const auto x = text.find_first_of("xX");
  if (x == std::string::npos) {
    const std::optional<double> value = to_number(text);
    if (!value || !(*value > 0))
      throw std::invalid_argument(error);
    return *value;
  }
  std::string rest = text.substr(x + 1);
  rest.erase(0, rest.find_first_not_of(" \t"));
  rest.erase(rest.find_last_not_of(" \t") + 1);
  const std::optional<double> factor = to_number(text.substr(0, x));
  if (!factor || !(*factor >= 1) || (rest != "Tolerance" && rest != "tolerance"))
    throw std::invalid_argument(error);
  return *factor * tolerance;
}

const ChoiceTable<SoleModel> sole_models{{SoleModel::linear, "linear"},
                                         {SoleModel::hyperelastic, "hyperelastic"}};
const ChoiceTable<contact::ContactSolverType> contact_solvers{
    {contact::ContactSolverType::admm, "admm"},
    {contact::ContactSolverType::gauss_seidel, "gauss-seidel"},
    {contact::ContactSolverType::newton, "newton"},
    {contact::ContactSolverType::automatic, "auto"}};
const ChoiceTable<walking::LegIkMethod> leg_ik_methods{
    {walking::LegIkMethod::automatic, "automatic"}, {walking::LegIkMethod::numerical, "numerical"}};
const ChoiceTable<FootstepPlacement> footstep_placements{{FootstepPlacement::flat, "flat"},
                                                         {FootstepPlacement::terrain, "terrain"}};
const ChoiceTable<StabilizerType> stabilizer_types{{StabilizerType::none, "none"},
                                                   {StabilizerType::dcm, "dcm"}};
const ChoiceTable<walking::StateEstimate> state_estimates{
    {walking::StateEstimate::kinematic, "kinematic"},
    {walking::StateEstimate::ground_truth, "ground truth"}};
const ChoiceTable<walking::PassiveJointEstimate> passive_joint_estimates{
    {walking::PassiveJointEstimate::plan, "plan"},
    {walking::PassiveJointEstimate::wrench, "wrench"}};

} // namespace

const char* contact_solver_name(contact::ContactSolverType solver) {
  return choice_name(contact_solvers, solver);
}

SoleModel sole_model(const fem::SoleParameters& sole) {
  return parse_choice(sole_models, sole.model, "Sole/Model");
}

std::vector<walking::Footstep> parse_footsteps(const std::string& text,
                                               const std::string& parameter) {
  std::vector<walking::Footstep> steps;
  std::stringstream all(text);
  std::string item;
  while (std::getline(all, item, ';')) {
    if (item.find_first_not_of(" \t") == std::string::npos)
      continue;
    std::stringstream fields(item);
    std::string field;
    double values[3];
    int n = 0;
    while (std::getline(fields, field, ',')) {
      const std::optional<double> value = to_number(field);
      if (!value || n == 3)
        throw std::invalid_argument(parameter + ": footstep '" + item +
                                    "' is not 'x, y, yaw' (three numbers: m, m, rad)");
      values[n++] = *value;
    }
    if (n != 3)
      throw std::invalid_argument(parameter + ": footstep '" + item +
                                  "' is not 'x, y, yaw' (three numbers: m, m, rad)");
    steps.push_back({values[0], values[1], values[2]});
  }
  return steps;
}

void RobotParameters::declare(dealii::ParameterHandler& prm) {
  prm.declare_entry("URDF file", "", Anything(),
                    "Robot model; relative paths: scene directory, then the Plantar tree. "
                    "Humanoid scenes must set it (e.g. by 'include models/hrp2/robot.prm').");
  prm.declare_entry("Foot form", to_string(RobotParameters().foot_form),
                    Selection(foot_form_names()), foot_form_help());
  prm.declare_entry("Foot forms", "",
                    dealii::Patterns::List(Selection(foot_form_names()), 0,
                                           static_cast<unsigned int>(foot_form_table().size())),
                    "Comparison of foot forms: plantar run runs the scene once per form listed "
                    "(e.g. 'rigid, compliant ankle, fem sole') into DIR/<form>/ and plots them "
                    "together into DIR/figures/; plantar sweep sweeps these forms. Empty: Foot "
                    "form only.");
  prm.declare_entry("Rigid foot grid", std::to_string(RobotParameters().rigid_foot_grid),
                    Integer(0, 15),
                    "Contact points of the rigid foot and the compliant ankle's foot: 0, the 8 "
                    "points of the sole outline (corners and edge midpoints); n in [2, 15], an n "
                    "x n grid over Sole/Length x Sole/Width, which also meets the ground under "
                    "the sole's interior (uneven ground: docs/terrain.md).");
  prm.declare_entry("Rigid sole depth warning",
                    number_text(RobotParameters().rigid_sole_depth_warning), Double(0, 1),
                    "Rigid feet and compliant ankles on uneven ground: warn when the deepest "
                    "point of the sole's face (an 11 x 11 grid over Sole/Length x Sole/Width) "
                    "is more than this in the ground (m), i.e. the contact points miss ground "
                    "under the sole; (0, 1].");
  prm.declare_entry("Rigid sole max depth", number_text(RobotParameters().rigid_sole_max_depth),
                    Double(0, 1),
                    "Same depth (m) at which the run stops, naming Robot/Rigid foot grid; "
                    "(0, 1].");
  prm.declare_entry("Ankle linear stiffness", "40000", Double(0),
                    "compliant ankle: vertical spring k_z (N/m), > 0.");
  prm.declare_entry("Ankle linear damping", "600", Double(0),
                    "compliant ankle: vertical damper c_z (N s/m).");
  prm.declare_entry("Ankle angular stiffness", "600", Double(0),
                    "compliant ankle: pitch and roll springs (N m/rad), > 0.");
  prm.declare_entry("Ankle angular damping", "60", Double(0),
                    "compliant ankle: pitch and roll dampers (N m s/rad).");
  prm.declare_entry("Ankle deflection compensation", "false", dealii::Patterns::Bool(),
                    "compliant ankle: offset the ankle pitch/roll references by the static "
                    "spring deflection tau/k that the reference's own ground wrench causes "
                    "(feed-forward as in HRP-2's controller; multibody/walking/"
                    "ankle_compensation.h).");
  prm.declare_entry("CoM height", "0.814", Double(0.1, 3.0),
                    "CoM height of the standing and walking posture above the sole frames (m); "
                    "sets the waist height.");
  prm.declare_entry("Base link", "", Anything(),
                    "The URDF's root link, the free-floating base (the waist: the waist figures "
                    "and the lean's roll are its pose). Humanoid scenes must set it.");
  prm.declare_entry("Right foot link", "", Anything(),
                    "The link under which the right sole is fixed; the actuated 1-DoF joints "
                    "from Base link down to it are the right leg (6 needed).");
  prm.declare_entry("Left foot link", "", Anything(), "Same for the left leg.");
  prm.declare_entry("Right sole frame", "", Anything(),
                    "A URDF link at the centre of the right sole's bottom face (z up, x "
                    "forward); empty: Right sole placement on the foot link.");
  prm.declare_entry("Left sole frame", "", Anything(), "Same for the left sole.");
  prm.declare_entry("Right sole placement", "0, 0, 0", Anything(),
                    "Used when Right sole frame is empty: the sole frame in the foot link frame, "
                    "'x, y, z' (m) or 'x, y, z, roll, pitch, yaw' (m, rad; URDF rpy).");
  prm.declare_entry("Left sole placement", "0, 0, 0", Anything(), "Same for the left sole.");
  prm.declare_entry("Controlled joints", "", Anything(),
                    "Comma-separated joints that the reference drives and the PD controller "
                    "tracks (the columns of joints.csv, in this order); empty: every actuated "
                    "joint of the URDF in model order. Must include both legs.");
  prm.declare_entry("Posture", "", Anything(),
                    "Standing posture, 'joint: angle, joint: angle, ...' in degrees (metres for "
                    "prismatic joints); joints not named are at 0; the leg joints are set by the "
                    "inverse kinematics (and are 0 in the drop scene).");
  prm.declare_entry("Leg IK", choice_name(leg_ik_methods, RobotParameters().leg_ik),
                    choice_pattern(leg_ik_methods),
                    "automatic: Kajita's closed form where a leg has HRP-2's structure "
                    "(yaw-roll-pitch hip, pitch knee, pitch-roll ankle, no offsets but a lateral "
                    "one at the knee), else the numerical SE(3) solver; numerical: always the "
                    "numerical solver.");
  prm.declare_entry("Ankle compliance centre", "0, 0, 0", Anything(),
                    "compliant ankle: centre of the ankle spring in the foot link frame, 'x, y, "
                    "z' (m).");
}

void RobotParameters::parse(dealii::ParameterHandler& prm,
                            const std::filesystem::path& scene_directory) {
  urdf_file = prm.get("URDF file").empty()
                  ? std::filesystem::path()
                  : fem::resolve_path(prm.get("URDF file"), scene_directory);
  if (!urdf_file.empty() && !std::filesystem::exists(urdf_file))
    throw std::invalid_argument("Robot/URDF file = " + prm.get("URDF file") + ": no such file (" +
                                urdf_file.string() + ")");
  foot_form = parse_foot_form(prm.get("Foot form"), "Robot/Foot form");
  rigid_foot_grid = static_cast<int>(prm.get_integer("Rigid foot grid"));
  require(rigid_foot_grid == 0 || (rigid_foot_grid >= 2 && rigid_foot_grid <= 15),
          "Robot/Rigid foot grid", rigid_foot_grid, "0 (the outline) or in [2, 15]");
  rigid_sole_depth_warning = prm.get_double("Rigid sole depth warning");
  rigid_sole_max_depth = prm.get_double("Rigid sole max depth");
  require(rigid_sole_depth_warning > 0, "Robot/Rigid sole depth warning", rigid_sole_depth_warning,
          "in (0, 1]");
  require(rigid_sole_max_depth > 0, "Robot/Rigid sole max depth", rigid_sole_max_depth,
          "in (0, 1]");
  foot_forms.clear();
  for (const std::string& item : dealii::Utilities::split_string_list(prm.get("Foot forms"), ','))
    foot_forms.push_back(parse_foot_form(item, "Robot/Foot forms"));
  ankle_linear_stiffness = prm.get_double("Ankle linear stiffness");
  ankle_linear_damping = prm.get_double("Ankle linear damping");
  ankle_angular_stiffness = prm.get_double("Ankle angular stiffness");
  ankle_deflection_compensation = prm.get_bool("Ankle deflection compensation");
  ankle_angular_damping = prm.get_double("Ankle angular damping");
  com_height = prm.get_double("CoM height");
  humanoid.base_link = prm.get("Base link");
  humanoid.foot_links = {prm.get("Right foot link"), prm.get("Left foot link")};
  humanoid.sole_frames = {prm.get("Right sole frame"), prm.get("Left sole frame")};
  humanoid.sole_placements = {
      parse_placement(prm.get("Right sole placement"), "Robot/Right sole placement"),
      parse_placement(prm.get("Left sole placement"), "Robot/Left sole placement")};
  humanoid.controlled_joints = dealii::Utilities::split_string_list(prm.get("Controlled joints"));
  humanoid.posture = parse_posture(prm.get("Posture"), "Robot/Posture");
  leg_ik = parse_choice(leg_ik_methods, prm.get("Leg IK"), "Robot/Leg IK");
  const std::vector<double> centre =
      parse_numbers(prm.get("Ankle compliance centre"), "Robot/Ankle compliance centre", 3, 3);
  ankle_compliance_centre << centre[0], centre[1], centre[2];
  require(ankle_linear_stiffness > 0, "Robot/Ankle linear stiffness", ankle_linear_stiffness,
          "> 0");
  require(ankle_angular_stiffness > 0, "Robot/Ankle angular stiffness", ankle_angular_stiffness,
          "> 0");
}

namespace {
const ChoiceTable<coupling::GridSpacing>& spacing_table() {
  static const ChoiceTable<coupling::GridSpacing> table{
      {coupling::GridSpacing::uniform, "uniform"}, {coupling::GridSpacing::chebyshev, "chebyshev"}};
  return table;
}
const ChoiceTable<coupling::PatchBasis>& basis_table() {
  static const ChoiceTable<coupling::PatchBasis> table{
      {coupling::PatchBasis::constant, "constant"}, {coupling::PatchBasis::bilinear, "bilinear"}};
  return table;
}
const ChoiceTable<coupling::ReductionQuantity>& quantity_table() {
  static const ChoiceTable<coupling::ReductionQuantity> table{
      {coupling::ReductionQuantity::stiffness, "stiffness"},
      {coupling::ReductionQuantity::pressure, "pressure"}};
  return table;
}
} // namespace

const char* reduction_quantity_name(coupling::ReductionQuantity quantity) {
  return choice_name(quantity_table(), quantity);
}

void SoleReductionParameters::declare(dealii::ParameterHandler& prm) {
  const SoleReductionParameters d;
  prm.declare_entry("Reduced patches", "0", Anything(),
                    "fem sole: 0 = the full condensed sole (one contact per bottom node); "
                    "'nx, ny' (integers >= 1) = a reduced sole: the bottom nodes grouped by an nx "
                    "x ny grid over the sole into patches (Sole/Reduction basis: its cells or "
                    "its vertices), one contact per patch with the patch-averaged compliance "
                    "A^T C A (coupling/reduced_sole.h; 3 solves per patch "
                    "with the kept factorization of K, no dense C; its fields recovered from the "
                    "patch forces for ParaView); 'auto' = the "
                    "coarsest g x g grid whose reduction error estimate meets Sole/Reduction "
                    "tolerance (g = 1, 2, 4, ... bracket it, then bisection), or the full sole "
                    "with a warning.");
  prm.declare_entry("Reduction spacing", choice_name(spacing_table(), d.spacing),
                    choice_pattern(spacing_table()),
                    "fem sole, Reduced patches: the grid's cells equal (uniform) or graded "
                    "towards the sole's edges, where a bonded layer's contact pressure peaks "
                    "(chebyshev: cell edges at the Chebyshev-Lobatto points; "
                    "coupling/reduced_sole.h).");
  prm.declare_entry("Reduction weights", d.area_weights ? "area" : "equal",
                    dealii::Patterns::Selection("area|equal"),
                    "fem sole, Reduced patches: how a patch's force is shared by its bottom nodes: "
                    "in proportion to their consistent areas (area: a uniform pressure over the "
                    "patch) or equally (equal); coupling/reduced_sole.h.");
  prm.declare_entry("Reduction basis", choice_name(basis_table(), d.basis),
                    choice_pattern(basis_table()),
                    "fem sole, Reduced patches: the pressure a patch force stands for: constant "
                    "over a grid cell (one contact per cell), or bilinear (one contact per grid "
                    "vertex, (nx + 1)(ny + 1) of them: the forces of a continuous pressure, "
                    "bilinear on each cell, interpolated from the vertices); "
                    "coupling/reduced_sole.h.");
  prm.declare_entry("Reduction tolerance", number_text(d.tolerance), Double(0, 1),
                    "fem sole, Reduced patches = auto: the bound on the reduction error estimate "
                    "of Sole/Reduction quantity, (0, 1). The summary reports both estimates of "
                    "every reduced sole (sole_reduction_estimate, "
                    "sole_reduction_pressure_estimate).");
  prm.declare_entry("Reduction quantity", choice_name(quantity_table(), d.quantity),
                    choice_pattern(quantity_table()),
                    "fem sole, Reduced patches = auto: what Sole/Reduction tolerance bounds: "
                    "stiffness = ||D^-1/2 (K - K_r) D^-1/2||_2, the relative error of the sole "
                    "face's stiffness against rigid motions (D = diag K), hence of its approach "
                    "and tilt under a given load; pressure = the worst relative L2 error of the "
                    "nodal normal contact forces of the face pressed flat onto the ground in any "
                    "approach, pitch and roll (coupling/reduced_sole.h).");
}

void SoleReductionParameters::parse(dealii::ParameterHandler& prm) {
  const std::string text = prm.get("Reduced patches");
  const auto items = dealii::Utilities::split_string_list(text, ',');
  bool ok = false;
  patches_x = patches_y = 0;
  tolerance = prm.get_double("Reduction tolerance");
  spacing = parse_choice(spacing_table(), prm.get("Reduction spacing"), "Sole/Reduction spacing");
  area_weights = prm.get("Reduction weights") == "area";
  basis = parse_choice(basis_table(), prm.get("Reduction basis"), "Sole/Reduction basis");
  quantity =
      parse_choice(quantity_table(), prm.get("Reduction quantity"), "Sole/Reduction quantity");
  automatic = items.size() == 1 && (items[0] == "auto" || items[0] == "Auto");
  require(tolerance > 0 && tolerance < 1, "Sole/Reduction tolerance", tolerance, "(0, 1)");
  if (automatic)
    return;
  try {
    if (items.size() == 1 && dealii::Utilities::string_to_int(items[0]) == 0) {
      ok = true;
    } else if (items.size() == 2) {
      patches_x = dealii::Utilities::string_to_int(items[0]);
      patches_y = dealii::Utilities::string_to_int(items[1]);
      ok = patches_x >= 1 && patches_y >= 1 && patches_x <= 1000 && patches_y <= 1000;
    }
  } catch (...) {
    ok = false;
  }
  if (!ok)
    throw std::invalid_argument(
        "Sole/Reduced patches = '" + text +
        "': allowed 0 (full sole), 'nx, ny' with integers in [1, 1000] or auto");
}

void SoleValidityParameters::declare(dealii::ParameterHandler& prm) {
  const SoleValidityParameters d;
  prm.declare_entry("Compression warning", number_text(d.compression_warning), Double(0, 1),
                    "Linear fem sole: a warning in the summary (first step, time, value, peak) "
                    "when a contact node is compressed by more than this fraction of "
                    "Sole/Thickness (u . n / t; small-strain theory), (0, 1].");
  prm.declare_entry("Max compression", number_text(d.max_compression), Double(0, 1),
                    "Linear fem sole: the run fails when a contact node is compressed by more "
                    "than this fraction of Sole/Thickness (the linear model far outside its "
                    "validity; the message names Sole/Model = hyperelastic), (0, 1].");
  prm.declare_entry("Strain warning", number_text(d.strain_warning), Double(0),
                    "Linear fem sole: a warning when a contact node's displacement exceeds this "
                    "fraction of Sole/Thickness (|u| / t: the strain through the thickness, "
                    "normal or shear), > 0.");
  prm.declare_entry("Max strain", number_text(d.max_strain), Double(0),
                    "Linear fem sole: the run fails when a contact node's displacement exceeds "
                    "this fraction of Sole/Thickness, > 0.");
  prm.declare_entry("Jacobian warning", number_text(d.jacobian_warning), Double(0, 1),
                    "Hyperelastic fem sole: a warning when det F at a quadrature point falls "
                    "below this (volume ratio), (0, 1).");
  prm.declare_entry("Min jacobian", number_text(d.min_jacobian), Double(0, 1),
                    "Hyperelastic fem sole: the run fails when det F at a quadrature point "
                    "falls below this (an element nearly inverted), (0, 1).");
}

void SoleValidityParameters::parse(dealii::ParameterHandler& prm) {
  compression_warning = prm.get_double("Compression warning");
  max_compression = prm.get_double("Max compression");
  strain_warning = prm.get_double("Strain warning");
  max_strain = prm.get_double("Max strain");
  jacobian_warning = prm.get_double("Jacobian warning");
  min_jacobian = prm.get_double("Min jacobian");
  require(compression_warning > 0, "Sole/Compression warning", compression_warning, "in (0, 1]");
  require(max_compression > 0, "Sole/Max compression", max_compression, "in (0, 1]");
  require(strain_warning > 0, "Sole/Strain warning", strain_warning, "> 0");
  require(max_strain > 0, "Sole/Max strain", max_strain, "> 0");
  require(jacobian_warning > 0 && jacobian_warning < 1, "Sole/Jacobian warning", jacobian_warning,
          "in (0, 1)");
  require(min_jacobian > 0 && min_jacobian < 1, "Sole/Min jacobian", min_jacobian, "in (0, 1)");
}

void ContactParameters::declare(dealii::ParameterHandler& prm) {
  prm.declare_entry("Friction coefficient", "0.8", Double(0, 10), "Coulomb mu, sole/ground.");
  prm.declare_entry("Restitution", "0", Double(0, 1), "Newton restitution e (paper eq. 5).");
  prm.declare_entry("Position correction", "0.2", Double(0, 1),
                    "Fraction of a penetration removed per step, (0, 1].");
  prm.declare_entry("Solver", choice_name(contact_solvers, ContactParameters().solver),
                    choice_pattern(contact_solvers),
                    "Contact solver (contact/, docs/contact_solvers.md): auto (Gauss-Seidel, "
                    "then semismooth Newton when it stalls), gauss-seidel, newton, admm.");
  prm.declare_entry("Tolerance", "1e-8", Double(0),
                    "Natural-map residual (m/s) at which a contact solve has converged, > 0.");
  prm.declare_entry("Max iterations", "500", Integer(1), "Solver iterations per step.");
  prm.declare_entry("Sticking direct solve", "true", Bool(),
                    "Before iterating, solve the sticking system of the warm start's contact "
                    "set directly and keep it if every impulse is in its cone and the "
                    "residual meets the tolerance (an exact solution); else iterate. Soles: "
                    "sliding nodes held, Woodbury over the factorised sole blocks, iterate "
                    "from the candidate. Rigid contacts (rigid feet, compliant ankles): the "
                    "impulses nearest the warm start by a pseudo-inverse, with active-set "
                    "rounds; iterate from the warm start (docs/contact.md).");
  prm.declare_entry("Sweep skip fraction", "0", Double(0, 1),
                    "Gauss-Seidel: a contact whose residual at its turn is at most this "
                    "fraction of the tolerance is left as it is for that sweep (no local "
                    "solve, no pass over its columns); convergence still needs every contact "
                    "within the tolerance. 0 updates every contact; [0, 1).");
  prm.declare_entry(
      "Newton stall iterations", std::to_string(ContactParameters().newton_stall_iterations),
      Integer(0),
      "auto: Newton from Gauss-Seidel's iterate stops after this many iterations "
      "without halving its residual; then Newton from the warm start (with the "
      "test), from zero, and if that fails from zero with a 10 x larger rho, then "
      "from Gauss-Seidel's iterate without the test (contact/auto_solver.h). 0: never "
      "stop early (nor the retries); >= 0.");
  prm.declare_entry("Failure residual", number_text(default_failure_factor) + " x Tolerance",
                    Anything(),
                    "A solve that stops unconverged with a residual above this stops the run "
                    "with an error suggesting what to change; below it the solve is counted "
                    "and listed in unconverged_solves.csv. A residual in m/s (> 0) or 'k x "
                    "Tolerance' (k >= 1).");
}

void ContactParameters::parse(dealii::ParameterHandler& prm) {
  friction = prm.get_double("Friction coefficient");
  restitution = prm.get_double("Restitution");
  position_correction = prm.get_double("Position correction");
  solver = parse_choice(contact_solvers, prm.get("Solver"), "Contact/Solver");
  tolerance = prm.get_double("Tolerance");
  max_iterations = prm.get_integer("Max iterations");
  sticking_direct = prm.get_bool("Sticking direct solve");
  sweep_skip = prm.get_double("Sweep skip fraction");
  newton_stall_iterations = static_cast<int>(prm.get_integer("Newton stall iterations"));
  failure_residual = parse_failure_residual(prm.get("Failure residual"), tolerance);
  require(sweep_skip < 1, "Contact/Sweep skip fraction", sweep_skip, "in [0, 1)");
  require(position_correction > 0, "Contact/Position correction", position_correction, "in (0, 1]");
  require(tolerance > 0, "Contact/Tolerance", tolerance, "> 0");
}

namespace {

/// The numbers of subsection Control's stabilizer, sensors and estimator: name, the member of
/// @p c it sets, lower bound, whether the bound is excluded, help. One table for declare()
/// and parse(), the defaults read from a default ControlParameters.
struct ControlNumber {
  const char* name;
  double* (*member)(ControlParameters&);
  double lower;
  bool strict;
  const char* help;
};

const std::vector<ControlNumber>& control_numbers() {
  using C = ControlParameters;
  static const std::vector<ControlNumber> table{
      {"DCM gain", [](C& c) { return &c.balance.stabilizer.dcm_gain; }, 0, false,
       "Stabilizer = dcm: k_p (1/s), the DCM error's closed-loop decay rate: desired ZMP p_d = "
       "p_ref + (1 + k_p/omega) e + k_i E (docs/stabilizer.md)."},
      {"DCM integral gain", [](C& c) { return &c.balance.stabilizer.dcm_integral_gain; }, 0, false,
       "k_i (1/s) on the leaky integral E of the DCM error."},
      {"DCM integral time constant",
       [](C& c) { return &c.balance.stabilizer.integral_time_constant; }, 0, true,
       "T_i (s): leak of the DCM error's integral, E' = e - E / T_i."},
      {"Foot damping", [](C& c) { return &c.balance.stabilizer.foot_damping; }, 0, true,
       "D (N m s/rad): foot damping control, rotation rate = CoP error x f_z / D (Kajita 2010)."},
      {"Foot damping rate", [](C& c) { return &c.foot_damping_rate; }, 0, false,
       "r (1/s), > 0: the foot damping of each axis set from what lies under the ankle, D = k / "
       "r with 1/k = 1/(Joint stiffness) + 1/(the foot's tilt stiffness: infinite for rigid "
       "feet, the ankle springs, a sole's whole face), the CoP loop's rate (docs/stabilizer.md); "
       "0: Foot damping on both axes."},
      {"Foot damping time constant", [](C& c) { return &c.balance.stabilizer.foot_time_constant; },
       0, true, "T_c (s): the foot rotations return to 0 with this time constant."},
      {"Force difference damping", [](C& c) { return &c.balance.stabilizer.force_damping; }, 0,
       true,
       "D_z (N s/m): foot force difference control, leg length rate = force difference "
       "error / D_z (Kajita 2010)."},
      {"Force difference time constant",
       [](C& c) { return &c.balance.stabilizer.force_time_constant; }, 0, true,
       "T_z (s): the leg length offset returns to 0 with this time constant."},
      {"Max foot rotation", [](C& c) { return &c.balance.stabilizer.max_foot_rotation; }, 0, false,
       "rad: clamp of each foot's roll and pitch offset."},
      {"Max leg length offset", [](C& c) { return &c.balance.stabilizer.max_leg_offset; }, 0, false,
       "m: clamp of the force difference control's leg length offset."},
      {"Min contact force", [](C& c) { return &c.balance.stabilizer.min_contact_force; }, 0, false,
       "N: a foot whose F/T sensor reads less has no CoP and does not anchor the estimate."},
      {"CoP margin", [](C& c) { return &c.cop_margin; }, 0, false,
       "m: CoP targets stay this far inside the sole outline (Sole/Length, Sole/Width), or "
       "inside each placement's support polygon (Walking/Footstep placement = terrain)."},
      {"ZMP filter time constant", [](C& c) { return &c.balance.zmp_time_constant; }, 0, true,
       "s: low-pass of the reference ZMP p_ref = xi_ref - xi_ref' / omega (finite differences)."},
      {"Velocity filter time constant",
       [](C& c) { return &c.balance.estimator.velocity_time_constant; }, 0, false,
       "s: low-pass of the estimated CoM velocity (finite difference of the kinematic CoM)."},
      {"Contact height", [](C& c) { return &c.balance.contact_height; }, 0, true,
       "m: a foot whose reference sole is within this of the ground may be in contact."},
      {"Touchdown force", [](C& c) { return &c.balance.touchdown.force; }, 0, true,
       "N: Touchdown adaptation: an F/T normal force above this marks the swing foot's "
       "touchdown (docs/stabilizer.md)."},
      {"Touchdown search velocity", [](C& c) { return &c.balance.touchdown.search_velocity; }, 0,
       true,
       "m/s: a foot that has not touched down when its plan is down moves down at this speed."},
      {"Max touchdown offset", [](C& c) { return &c.balance.touchdown.max_offset; }, 0, true,
       "m: clamp of the ground level a foot finds above or below its plan."},
      {"Step adjustment gain", [](C& c) { return &c.balance.step.gain; }, 0, false,
       "k_s, [0, 2]: Step adjustment: the landing moves by k_s times the DCM error the stance "
       "sole cannot take, carried to the planned touchdown (docs/stabilizer.md)."},
      {"Max step adjustment forward", [](C& c) { return &c.balance.step.max_forward; }, 0, true,
       "m: clamp of a landing's move along the sole's x axis (either way)."},
      {"Max step adjustment outward", [](C& c) { return &c.balance.step.max_outward; }, 0, false,
       "m: clamp of a landing's move sideways, away from the stance foot."},
      {"Max step adjustment inward", [](C& c) { return &c.balance.step.max_inward; }, 0, false,
       "m: clamp of a landing's move sideways, towards the stance foot."},
      {"Step adjustment CoP margin", [](C& c) { return &c.balance.step.cop_margin; }, 0, false,
       "m: a landing moves once the reference ZMP plus the DCM error leaves the stance sole's "
       "CoP region (CoP margin) shrunk by this further (0: what the ankle can take, LIPM)."},
      {"Max step adjustment speed", [](C& c) { return &c.balance.step.max_target_speed; }, 0, true,
       "m/s: a landing target moves at most this fast."},
      {"Step adjustment freeze time", [](C& c) { return &c.balance.step.freeze_time; }, 0, false,
       "s: over the last this much of a swing the landing is held."},
      {"Step timing time constant", [](C& c) { return &c.balance.timing.time_constant; }, 0, true,
       "T_t, s: Step timing: the reference runs at 1 + lambda / T_t, lambda the time by which it "
       "must move ahead to take the DCM error along its motion (docs/stabilizer.md)."},
      {"Max step timing rate", [](C& c) { return &c.balance.timing.max_rate; }, 1, false,
       "Step timing: the reference runs at most this many times as fast as the plan."},
      {"Step timing freeze time", [](C& c) { return &c.balance.timing.freeze_time; }, 0, false,
       "s: over the last this much of a swing (reference time) the reference runs at the plan's "
       "rate."},
      {"IMU orientation noise", [](C& c) { return &c.balance.sensors.orientation.noise; }, 0, false,
       "rad, standard deviation of the IMU orientation's white noise (rotation vector)."},
      {"IMU orientation bias", [](C& c) { return &c.balance.sensors.orientation.bias; }, -1e300,
       false, "rad, on each axis of the rotation vector."},
      {"Gyro noise", [](C& c) { return &c.balance.sensors.angular_velocity.noise; }, 0, false,
       "rad/s, standard deviation."},
      {"Gyro bias", [](C& c) { return &c.balance.sensors.angular_velocity.bias; }, -1e300, false,
       "rad/s."},
      {"Accelerometer noise", [](C& c) { return &c.balance.sensors.linear_acceleration.noise; }, 0,
       false, "m/s^2, standard deviation."},
      {"Accelerometer bias", [](C& c) { return &c.balance.sensors.linear_acceleration.bias; },
       -1e300, false, "m/s^2."},
      {"Encoder noise", [](C& c) { return &c.balance.sensors.encoder.noise; }, 0, false,
       "rad, standard deviation."},
      {"Encoder bias", [](C& c) { return &c.balance.sensors.encoder.bias; }, -1e300, false, "rad."},
      {"Force noise", [](C& c) { return &c.balance.sensors.force.noise; }, 0, false,
       "N, standard deviation (F/T sensors)."},
      {"Force bias", [](C& c) { return &c.balance.sensors.force.bias; }, -1e300, false, "N."},
      {"Torque noise", [](C& c) { return &c.balance.sensors.torque.noise; }, 0, false,
       "N m, standard deviation (F/T sensors)."},
      {"Torque bias", [](C& c) { return &c.balance.sensors.torque.bias; }, -1e300, false, "N m."},
      {"Force sensor bandwidth", [](C& c) { return &c.balance.sensors.force_bandwidth; }, 0, false,
       "Hz: cut-off of a first-order low-pass on both F/T sensors' six signals, after their "
       "delay, bias and noise (the sensor's and its amplifier's bandwidth); 0: none."},
  };
  return table;
}

} // namespace

void ControlParameters::declare(dealii::ParameterHandler& prm) {
  prm.declare_entry("Joint stiffness", "10000", Double(0),
                    "PD kp on every actuated joint (N m/rad): tau = kp (q_ref - q) + kd (v_ref - "
                    "v), applied implicitly by the stepper.");
  prm.declare_entry("Joint damping", "200", Double(0), "PD kd (N m s/rad).");
  ControlParameters d;
  prm.declare_entry("Stabilizer", choice_name(stabilizer_types, d.stabilizer),
                    choice_pattern(stabilizer_types),
                    "none: PD playback of the reference (the paper's); dcm: the sensor-based "
                    "DCM stabilizer changing the joint references (docs/stabilizer.md).");
  prm.declare_entry("State estimate", choice_name(state_estimates, d.balance.estimate),
                    choice_pattern(state_estimates),
                    "kinematic: CoM and DCM from encoders, IMU orientation and the F/T "
                    "sensors' contact anchoring; ground truth: the simulator's (comparison).");
  prm.declare_entry("Passive joint estimate",
                    choice_name(passive_joint_estimates, d.balance.estimator.passive),
                    choice_pattern(passive_joint_estimates),
                    "State estimate = kinematic, passive joints with springs (Robot/Foot form = "
                    "compliant ankle): plan: at the plan's predicted deflection; wrench: each "
                    "spring-damper driven by the F/T sensors' wrenches, c q' + k (q - rest) = "
                    "J^T W (multibody/walking/com_estimator.h).");
  for (const ControlNumber& entry : control_numbers())
    prm.declare_entry(entry.name, number_text(*entry.member(d)),
                      entry.lower < -1e299 ? Double() : Double(entry.lower), entry.help);
  prm.declare_entry("Touchdown adaptation", d.balance.touchdown.enabled ? "true" : "false", Bool(),
                    "Stabilizer = dcm: each swing foot stops where it touches the ground early "
                    "and searches downwards when late; the foot keeps the level it found "
                    "(multibody/walking/touchdown_adaptation.h).");
  prm.declare_entry("Step adjustment", d.balance.step.enabled ? "true" : "false", Bool(),
                    "Stabilizer = dcm: where the stance sole cannot take the desired ZMP, the "
                    "swing foot lands elsewhere and the rest of the walk is translated with it "
                    "(multibody/walking/step_adjustment.h).");
  prm.declare_entry("Step timing", d.balance.timing.enabled ? "true" : "false", Bool(),
                    "Stabilizer = dcm: where the stance sole cannot take the DCM error along the "
                    "reference's motion, the reference runs faster and the swing foot lands "
                    "earlier (multibody/walking/step_timing.h).");
  prm.declare_entry("Step adjustment leg iterations", std::to_string(d.balance.step.leg_iterations),
                    Integer(0, 10),
                    "Step adjustment: Newton steps bringing each leg to its offset sole pose "
                    "after the linear (Jacobian) step, [0, 10].");
  prm.declare_entry("Sensor delay", std::to_string(d.balance.sensors.delay), Integer(0, 1000),
                    "Every sensor's delay in control periods (= Simulation/Time step).");
  prm.declare_entry("Sensor seed", std::to_string(d.balance.sensors.seed), Integer(0),
                    "Seed of the sensors' noise generator.");
  prm.declare_entry("IMU frame", "", Anything(),
                    "Frame (URDF link) of the IMU; empty: Robot/Base link.");
  prm.declare_entry("Right force sensor frame", "", Anything(),
                    "Frame of the right ankle's 6-axis F/T sensor, on the foot link's body; "
                    "empty: Robot/Right foot link.");
  prm.declare_entry("Left force sensor frame", "", Anything(), "Same for the left foot.");
}

void ControlParameters::parse(dealii::ParameterHandler& prm) {
  stiffness = prm.get_double("Joint stiffness");
  damping = prm.get_double("Joint damping");
  stabilizer = parse_choice(stabilizer_types, prm.get("Stabilizer"), "Control/Stabilizer");
  balance.estimate =
      parse_choice(state_estimates, prm.get("State estimate"), "Control/State estimate");
  balance.estimator.passive = parse_choice(
      passive_joint_estimates, prm.get("Passive joint estimate"), "Control/Passive joint estimate");
  for (const ControlNumber& entry : control_numbers()) {
    const double value = prm.get_double(entry.name);
    require(entry.strict ? value > entry.lower : value >= entry.lower,
            std::string("Control/") + entry.name, value,
            (entry.strict ? "> " : ">= ") + number_text(entry.lower));
    *entry.member(*this) = value;
  }
  balance.touchdown.enabled = prm.get_bool("Touchdown adaptation");
  balance.step.enabled = prm.get_bool("Step adjustment");
  balance.step.leg_iterations = prm.get_integer("Step adjustment leg iterations");
  balance.timing.enabled = prm.get_bool("Step timing");
  require(balance.step.gain <= 2, "Control/Step adjustment gain", balance.step.gain, "in [0, 2]");
  balance.sensors.delay = prm.get_integer("Sensor delay");
  require(balance.sensors.delay >= 0 && balance.sensors.delay <= 1000, "Control/Sensor delay",
          balance.sensors.delay, "in [0, 1000] control periods");
  const long seed = prm.get_integer("Sensor seed");
  require(seed >= 0 && seed <= 4294967295L, "Control/Sensor seed", static_cast<double>(seed),
          "in [0, 2^32 - 1]");
  balance.sensors.seed = static_cast<std::uint32_t>(seed);
  imu_frame = prm.get("IMU frame");
  force_frames = {prm.get("Right force sensor frame"), prm.get("Left force sensor frame")};
}

void WalkingSceneParameters::declare(dealii::ParameterHandler& prm) {
  const walking::WalkingParameters d;
  prm.declare_entry("Single support time", "0.78", Double(0, 10), "s, [0, 10] (HRP-2: 0.78).");
  prm.declare_entry("Double support time", "0.02", Double(0, 10),
                    "s, between steps, [0, 10] (HRP-2: 0.02).");
  prm.declare_entry("Initial double support time", "0.6", Double(0, 10),
                    "s, ZMP from the feet centre to the first support foot, [0, 10].");
  prm.declare_entry("Final double support time", "0.62", Double(0, 10),
                    "s, ZMP back to the feet centre, [0, 10].");
  prm.declare_entry("Standing before", "1.0", Double(0, 60),
                    "s, standing still before the walk, [0, 60].");
  prm.declare_entry("Standing after", "1.0", Double(0, 60),
                    "s, standing still after the walk, [0, 60].");
  prm.declare_entry("Step height", "0.07", Double(0, 0.3), "Swing-foot apex (m).");
  prm.declare_entry("Touchdown velocity", number_text(d.touchdown_velocity), Double(0, 1),
                    "Planned downward speed of the swing sole at touchdown (m/s), [0, 1] and at "
                    "most 19 Step height / Single support time (the apex stays at Step height); "
                    "0: it lands at rest (the paper's walk). docs/walking.md.");
  prm.declare_entry("Max step length", "0.45", Double(0), "Longest swing travel allowed (m).");
  prm.declare_entry("Right foot first", "true", Bool(), "The right foot swings first.");
  prm.declare_entry("Initial right sole", "0, -0.105, 0", Anything(), "x, y, yaw (m, m, rad).");
  prm.declare_entry("Initial left sole", "0, 0.105, 0", Anything(), "x, y, yaw (m, m, rad).");
  prm.declare_entry("Footsteps", footsteps_text(d.footsteps), Anything(),
                    "Landing placements of the successive swing feet (alternating), "
                    "'x, y, yaw; x, y, yaw; ...' (m, m, rad); default: the paper's six steps.");
  prm.declare_entry("Preview time", "1.6", Double(0, 10),
                    "Preview horizon (s), [0, 10], Kajita 2003.");
  const WalkingSceneParameters w;
  prm.declare_entry("Footstep placement", choice_name(footstep_placements, w.placement),
                    choice_pattern(footstep_placements),
                    "flat: the walk is planned on a level ground (raised once onto the highest "
                    "ground under the feet at t = 0); terrain: each placement (initial soles and "
                    "footsteps) rests on the terrain on three of the foot's contact points, its "
                    "centre carried, none below the ground (docs/terrain.md).");
  prm.declare_entry("Footprint samples", std::to_string(w.footprint_samples), Integer(2, 100),
                    "Footstep placement = terrain with a foot of more than (samples)^2 contact "
                    "points: an samples x samples grid over Sole/Length x Sole/Width stands for "
                    "them, [2, 100].");
  prm.declare_entry("ZMP support margin", std::to_string(w.zmp_margin), Double(0, 0.1),
                    "Footstep placement = terrain: the ZMP reference rests on each sole at the "
                    "point of its support (the hull of its contact points on the ground: three on "
                    "a rough ground) at least this far inside it (m), nearest to the sole centre "
                    "(docs/terrain.md), [0, 0.1].");
  prm.declare_entry("Foothold search radius", number_text(w.foothold.radius), Double(0, 0.1),
                    "Footstep placement = terrain: each footstep may move horizontally by up to "
                    "this distance (m) to a placement whose support holds the sole centre at least "
                    "ZMP support margin inside (else as far inside as the candidates allow), the "
                    "nearest such to the plan; the steps stay within Max step length; 0: the "
                    "footsteps stay where planned (docs/terrain.md), [0, 0.1].");
  prm.declare_entry("Swing ground margin", number_text(d.swing_ground_margin), Double(0, 0.05),
                    "Footstep placement = terrain: each swing sole stays this far above the ground "
                    "between its placements (m; or as high as the plan lifts it, if lower), by "
                    "lifting the foot before it moves over higher ground (Footstep::lift_fraction, "
                    "docs/terrain.md), [0, 0.05].");
  prm.declare_entry("Min lift fraction", number_text(d.min_lift_fraction), Double(0, 0.45),
                    "Every swing moves only vertically over at least this fraction of the single "
                    "support at each end (lift-off and touchdown), [0, 0.45]: over a ground the "
                    "plan does not know, the foot rises before it moves; 0: the paper's swing.");
  prm.declare_entry("Foothold search spacing", number_text(w.foothold.spacing), Double(0.001, 0.05),
                    "Grid spacing of the foothold search's candidate positions (m), [0.001, "
                    "0.05]; (2 radius / spacing + 1)^2 placements per footstep at most.");
  prm.declare_entry("Foothold max tilt", number_text(w.foothold.max_tilt), Double(0.001, 0.5),
                    "The foothold search leaves out placements tilted more than this (rad) and "
                    "more than the planned one (a sole bridging a step's edge rests on the edge "
                    "line), [0.001, 0.5].");
}

void WalkingSceneParameters::parse(dealii::ParameterHandler& prm) {
  walk.single_support_time = prm.get_double("Single support time");
  walk.double_support_time = prm.get_double("Double support time");
  walk.initial_double_support_time = prm.get_double("Initial double support time");
  walk.final_double_support_time = prm.get_double("Final double support time");
  walk.standing_before = prm.get_double("Standing before");
  walk.standing_after = prm.get_double("Standing after");
  walk.step_height = prm.get_double("Step height");
  walk.touchdown_velocity = prm.get_double("Touchdown velocity");
  walk.swing_ground_margin = prm.get_double("Swing ground margin");
  walk.min_lift_fraction = prm.get_double("Min lift fraction");
  walk.max_step_length = prm.get_double("Max step length");
  walk.right_foot_first = prm.get_bool("Right foot first");
  walk.initial_right = parse_one(prm.get("Initial right sole"), "Walking/Initial right sole");
  walk.initial_left = parse_one(prm.get("Initial left sole"), "Walking/Initial left sole");
  walk.footsteps = parse_footsteps(prm.get("Footsteps"), "Walking/Footsteps");
  if (walk.footsteps.empty())
    throw std::invalid_argument("Walking/Footsteps is empty: give at least one 'x, y, yaw'");
  preview_time = prm.get_double("Preview time");
  placement = parse_choice(footstep_placements, prm.get("Footstep placement"),
                           "Walking/Footstep placement");
  footprint_samples = static_cast<int>(prm.get_integer("Footprint samples"));
  zmp_margin = prm.get_double("ZMP support margin");
  foothold.radius = prm.get_double("Foothold search radius");
  foothold.spacing = prm.get_double("Foothold search spacing");
  foothold.max_tilt = prm.get_double("Foothold max tilt");
  try {
    walking::check_walking_parameters(walk);
  } catch (const std::invalid_argument& e) {
    throw std::invalid_argument(std::string("Walking: ") + e.what());
  }
  require(preview_time > 0, "Walking/Preview time", preview_time, "> 0");
}

void LeanSceneParameters::declare(dealii::ParameterHandler& prm) {
  prm.declare_entry("Final angle", "14.3", Double(-20, 20),
                    "Waist roll commanded at the end of the ramp (deg; paper: 14.3).");
  // Bounded: the reference is sampled over the whole test (an unbounded time overflowed its
  // sample count).
  prm.declare_entry("Start time", "0.5", Double(0, 600), "Standing before the ramp (s), [0, 600].");
  prm.declare_entry("Ramp time", "3.0", Double(0, 600), "Quintic ramp duration (s), (0, 600].");
  prm.declare_entry("Hold time", "2.0", Double(0, 600), "Holding the final angle (s), [0, 600].");
}

void LeanSceneParameters::parse(dealii::ParameterHandler& prm) {
  final_angle_deg = prm.get_double("Final angle");
  start_time = prm.get_double("Start time");
  ramp_time = prm.get_double("Ramp time");
  hold_time = prm.get_double("Hold time");
  require(ramp_time > 0, "Lean/Ramp time", ramp_time, "> 0");
}

void SimulationParameters::declare(dealii::ParameterHandler& prm) {
  prm.declare_entry("Time step", "0.001", Double(0, 0.01), "dt (s), (0, 0.01].");
  prm.declare_entry("Theta", "1", Double(0.5, 1),
                    "Moreau-Jean theta, [0.5, 1]: weight of the step's end in the joint springs, "
                    "the sole forces and the position update. 1: the paper's eq. 4 (first "
                    "order, damps stiff springs); 0.5: second order, no numerical damping. The "
                    "passive joints take Passive joint theta.");
  prm.declare_entry(
      "Passive joint theta", number_text(SimulationParameters{}.passive_joint_theta),
      Double(0.5, 1),
      "Moreau-Jean theta of the passive joints (Robot/Foot form = compliant ankle: the ankle "
      "springs), [0.5, 1], in place of Theta for them. 1 (backward Euler) damps the foot's "
      "fast overdamped mode on its spring, which at 0.5 rings at the step's frequency (the "
      "contact force alternates by hundreds of N from step to step; docs/reproduction.md).");
  prm.declare_entry(
      "Duration", "0", Double(0, 3600),
      "Simulated time (s), [0, 3600]; 0: the whole reference (lean, walk) or 5 s plus the "
      "settle time (stand), 1 s (drop).");
  prm.declare_entry("Settle time", "1.0", Double(0, 600),
                    "stand: time to settle before the 1 mm window is measured (s), [0, 600].");
  prm.declare_entry("Release height", "0.01", Double(0, 0.5),
                    "drop: height of the lowest contact point above the ground at release (m).");
  prm.declare_entry("Drop posture", "", Anything(),
                    "drop: joint angles held during the drop, 'joint: angle, ...' in degrees "
                    "(metres for prismatic joints), over straight legs and Robot/Posture "
                    "(e.g. bent knees for a drop onto knee pads).");
  const SimulationParameters d;
  prm.declare_entry("Fall height", number_text(d.fall_height), Double(0),
                    "The run fails (non-zero exit) if the waist goes below this height (m).");
  prm.declare_entry("Fall tilt", number_text(d.fall_tilt), Double(0, 180),
                    "deg, (0, 180]: the run fails if the waist's z axis tilts further than this "
                    "from the reference waist's (a robot lying on its side can keep its waist "
                    "above Fall height).");
  prm.declare_entry("Max penetration", number_text(d.max_penetration), Double(0),
                    "The run fails if a contact point sinks deeper than this into the ground (m).");
  prm.declare_entry("Push time", number_text(d.push_time), Double(0, 3600),
                    "s, [0, 3600]: start of a push on the waist (base origin).");
  prm.declare_entry("Push direction",
                    number_text(d.push_direction.x()) + ", " + number_text(d.push_direction.y()) +
                        ", " + number_text(d.push_direction.z()),
                    Anything(), "'x, y, z' (world axes, normalised): direction of the push.");
  prm.declare_entry("Push magnitude", number_text(d.push_magnitude), Double(0),
                    "N s: impulse of the push, a constant force over Push duration; 0: no push.");
  prm.declare_entry("Push duration", number_text(d.push_duration), Double(0, 600),
                    "s, (0, 600]: duration of the push.");
}

void SimulationParameters::parse(dealii::ParameterHandler& prm) {
  time_step = prm.get_double("Time step");
  theta = prm.get_double("Theta");
  passive_joint_theta = prm.get_double("Passive joint theta");
  duration = prm.get_double("Duration");
  settle_time = prm.get_double("Settle time");
  release_height = prm.get_double("Release height");
  drop_posture = parse_posture(prm.get("Drop posture"), "Simulation/Drop posture");
  fall_height = prm.get_double("Fall height");
  fall_tilt = prm.get_double("Fall tilt");
  require(fall_tilt > 0, "Simulation/Fall tilt", fall_tilt, "(0, 180] deg");
  max_penetration = prm.get_double("Max penetration");
  push_time = prm.get_double("Push time");
  const std::vector<double> direction =
      parse_numbers(prm.get("Push direction"), "Simulation/Push direction", 3, 3);
  push_direction << direction[0], direction[1], direction[2];
  require(push_direction.norm() > 0, "Simulation/Push direction |.|", push_direction.norm(), "> 0");
  push_direction.normalize();
  push_magnitude = prm.get_double("Push magnitude");
  push_duration = prm.get_double("Push duration");
  require(push_duration > 0, "Simulation/Push duration", push_duration, "> 0 s");
  require(time_step > 0, "Simulation/Time step", time_step, "in (0, 0.01]");
  require(max_penetration > 0, "Simulation/Max penetration", max_penetration, "> 0");
}

} // namespace plantar::app
