#include "fem/sole_parameters.h"

#include "fem/hyperelastic_material_table.h"
#include "fem/material_table.h"

#include <cmath>
#include <cstdlib>
#include <sstream>
#include <stdexcept>

namespace plantar::fem {

using dealii::Patterns::Bool;
using dealii::Patterns::Double;
using dealii::Patterns::Integer;
using dealii::Patterns::Selection;
using Anything = dealii::Patterns::Anything;

namespace {

double positive(dealii::ParameterHandler& prm, const std::string& name) {
  const double value = prm.get_double(name);
  if (!(value > 0)) {
    std::ostringstream msg;
    msg << "Sole/" << name << " = " << value << " is out of range: must be > 0";
    throw std::invalid_argument(msg.str());
  }
  return value;
}

/// Cells a mesh of the sole's box may have (a dense condensed operator of its bottom face is
/// out of reach long before).
constexpr double kMaxSoleCells = 2e6;

} // namespace

void SoleParameters::declare(dealii::ParameterHandler& prm) {
  prm.declare_entry("Geometry file", "meshes/sole_box.geo", Anything(),
                    "gmsh .geo source of the sole (physical surfaces 'top', 'bottom'; one "
                    "physical volume per material region). Relative to the scene file, then to "
                    "the Plantar source tree.");
  prm.declare_entry("Length", "0.2172", Double(0, 2), "Sole length along x (m), (0, 2].");
  prm.declare_entry("Width", "0.138", Double(0, 2), "Sole width along y (m), (0, 2].");
  prm.declare_entry("Thickness", "0.020", Double(0, 0.5), "Sole thickness along z (m), (0, 0.5].");
  prm.declare_entry("Mesh size", "0.008", Double(0, 0.5),
                    "Target element edge length (m), (0, 0.5]; at most 2e6 cells in the sole's "
                    "box (Length x Width x Thickness / Mesh size^3).");
  prm.declare_entry("Cell kind", "tetrahedron", Selection("tetrahedron|hexahedron"),
                    "Tetrahedra (P elements) or hexahedra (Q elements).");
  prm.declare_entry("Element degree", "1", Integer(1, 2), "1 (P1/Q1) or 2 (P2/Q2).");
  prm.declare_entry("Materials", "rubber: E=4e6, nu=0.3", Anything(),
                    "Material per physical volume: 'region: law=linear, E=<Pa>, nu=<->; ...' "
                    "with E > 0 and -1 < nu < 0.5.");
  prm.declare_entry("Model", "linear", Selection("linear|hyperelastic"),
                    "linear: the sole is condensed once (Materials with law=linear). "
                    "hyperelastic: Materials with law=neo_hookean or mooney_rivlin; the tangent "
                    "compliance is re-condensed in the time loop when its prediction error "
                    "exceeds the Recondensation tolerance (docs/nonlinear_soles.md).");
  prm.declare_entry("Formulation", "displacement", Selection("displacement|mixed"),
                    "Hyperelastic only: displacement, or mixed u-p (nearly incompressible; Q1-P0 "
                    "/ Q2-P1 on hexahedra, P2-P0 on tetrahedra).");
  prm.declare_entry("Recondensation tolerance", "0.02", Double(0),
                    "Hyperelastic only: re-condense when the relative error of the predicted "
                    "contact displacements exceeds this, > 0.");
  prm.declare_entry("Check tolerance", "0.02", Double(0, 1),
                    "Hyperelastic only: Newton check of the sole when the contact forces moved "
                    "by more than this fraction since the last check, [0, 1].");
  prm.declare_entry("Damping time", "0", Double(0, 0.1),
                    "Linear model only: Kelvin-Voigt damping time beta (s), [0, 0.1]: "
                    "stiffness-proportional material damping D = beta K (loss factor beta omega "
                    "at angular frequency omega); 0: elastic, as in the paper.");
  prm.declare_entry("Linear solver", "direct", Selection("direct|iterative"),
                    "Sparse direct (UMFPACK) or PETSc CG + BoomerAMG for large meshes.");
  prm.declare_entry("Iterative tolerance", "1e-10", Double(1e-16, 1e-2),
                    "Relative residual tolerance of the iterative solver.");
  prm.declare_entry("Mesh cache directory", "", Anything(),
                    "Where generated meshes are cached; empty: $PLANTAR_MESH_CACHE, "
                    "$XDG_CACHE_HOME/plantar/meshes or ~/.cache/plantar/meshes.");
}

void SoleParameters::parse(dealii::ParameterHandler& prm,
                           const std::filesystem::path& scene_directory) {
  geometry_file = resolve_path(prm.get("Geometry file"), scene_directory);
  if (!std::filesystem::exists(geometry_file))
    throw std::invalid_argument("Sole/Geometry file = '" + prm.get("Geometry file") +
                                "': no such file (looked in '" + scene_directory.string() +
                                "' and the Plantar source tree)");
  length = positive(prm, "Length");
  width = positive(prm, "Width");
  thickness = positive(prm, "Thickness");
  mesh_size = positive(prm, "Mesh size");
  const double cells = std::ceil(length / mesh_size) * std::ceil(width / mesh_size) *
                       std::ceil(thickness / mesh_size);
  if (!(cells <= kMaxSoleCells)) {
    std::ostringstream msg;
    msg << "Sole/Mesh size = " << mesh_size << " m gives about " << cells << " cells for a sole of "
        << length << " x " << width << " x " << thickness
        << " m (Length x Width x Thickness / Mesh size^3): allowed up to " << kMaxSoleCells
        << "; use a coarser mesh";
    throw std::invalid_argument(msg.str());
  }
  cell_kind = prm.get("Cell kind") == "hexahedron" ? CellKind::hexahedron : CellKind::tetrahedron;
  degree = prm.get_integer("Element degree");
  materials = prm.get("Materials");
  model = prm.get("Model");
  mixed = prm.get("Formulation") == "mixed";
  recondensation_tolerance = positive(prm, "Recondensation tolerance");
  check_tolerance = prm.get_double("Check tolerance");
  damping_time = prm.get_double("Damping time");
  if (damping_time > 0 && model != "linear")
    throw std::invalid_argument("Sole/Damping time = " + prm.get("Damping time") +
                                " s with Sole/Model = " + model +
                                ": damping is for the linear model only (allowed: 0)");
  // Check the linear laws' parameters now, so errors name the scene; other
  // laws are checked by their own classes.
  for (const auto& [region, spec] : parse_material_specs(materials, "Sole/Materials"))
    if (spec.law == "linear") {
      const auto get = [&](const std::string& key) {
        const auto it = spec.values.find(key);
        if (it == spec.values.end())
          throw std::invalid_argument("Sole/Materials: region '" + region + "' lacks '" + key +
                                      "'");
        return it->second;
      };
      try {
        LinearElasticMaterial(get("E"), get("nu"), region);
      } catch (const std::invalid_argument& e) {
        throw std::invalid_argument(std::string("Sole/Materials: ") + e.what());
      }
    }
  if (model == "hyperelastic")
    for (const auto& [region, spec] : parse_material_specs(materials, "Sole/Materials")) {
      try {
        make_hyperelastic_law(spec);
      } catch (const std::invalid_argument& e) {
        throw std::invalid_argument("Sole/Materials (Sole/Model = hyperelastic): region '" +
                                    region + "': " + e.what());
      }
    }
  solver.kind = LinearSolverSettings::parse_kind(prm.get("Linear solver"));
  solver.relative_tolerance = prm.get_double("Iterative tolerance");
  const std::string cache = prm.get("Mesh cache directory");
  cache_directory = cache.empty() ? std::filesystem::path() : resolve_path(cache, scene_directory);
}

MeshRequest SoleParameters::mesh_request() const {
  MeshRequest request;
  request.geo_file = geometry_file;
  request.numbers = {{"SoleLength", length},
                     {"SoleWidth", width},
                     {"SoleThickness", thickness},
                     {"SoleMeshSize", mesh_size},
                     {"SoleHex", cell_kind == CellKind::hexahedron ? 1.0 : 0.0}};
  request.cache_directory = cache_directory;
#ifdef PLANTAR_GMSH_EXECUTABLE
  request.gmsh_executable = PLANTAR_GMSH_EXECUTABLE;
#endif
  return request;
}

std::filesystem::path default_mesh_cache() {
  if (const char* dir = std::getenv("PLANTAR_MESH_CACHE"); dir && *dir)
    return dir;
  if (const char* dir = std::getenv("XDG_CACHE_HOME"); dir && *dir)
    return std::filesystem::path(dir) / "plantar" / "meshes";
  if (const char* home = std::getenv("HOME"); home && *home)
    return std::filesystem::path(home) / ".cache" / "plantar" / "meshes";
  return std::filesystem::temp_directory_path() / "plantar-meshes";
}

std::filesystem::path resolve_path(const std::filesystem::path& path,
                                   const std::filesystem::path& scene_directory) {
  if (path.is_absolute())
    return path;
  if (std::filesystem::exists(scene_directory / path))
    return scene_directory / path;
#ifdef PLANTAR_SOURCE_DIR
  return std::filesystem::path(PLANTAR_SOURCE_DIR) / path;
#else
  return scene_directory / path;
#endif
}

} // namespace plantar::fem
