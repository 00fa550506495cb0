#pragma once
// Scene parameters of a sole (subsection "Sole" of a .prm scene file):
// geometry source and sizes, mesh, element, materials and linear solver.

#include "fem/linear_solver.h"
#include "fem/mesh_generator.h"
#include "fem/mesh_import.h"

#include <deal.II/base/parameter_handler.h>

#include <filesystem>
#include <string>

namespace plantar::fem {

struct SoleParameters {
  std::filesystem::path geometry_file = "meshes/sole_box.geo";
  double length = 0.2172;   ///< m (HRP-2's foot)
  double width = 0.138;     ///< m
  double thickness = 0.020; ///< m (the paper's 2 cm)
  double mesh_size = 0.008; ///< m, target edge length
  CellKind cell_kind = CellKind::tetrahedron;
  unsigned int degree = 1;                         ///< 1 (P1/Q1) or 2 (P2/Q2)
  std::string materials = "rubber: E=4e6, nu=0.3"; ///< see fem/material_table.h
  /// "linear" (condensed once) or "hyperelastic" (laws of fem/hyperelastic_material_table.h,
  /// tangent re-condensed in the time loop: coupling/nonlinear_condensed_sole.h).
  std::string model = "linear";
  bool mixed = false;                     ///< hyperelastic: mixed u-p formulation (no locking)
  double recondensation_tolerance = 0.02; ///< hyperelastic: prediction error e, > 0
  double check_tolerance = 0.02;          ///< hyperelastic: relative force change, [0, 1]
  /// Kelvin-Voigt damping time beta (s), [0, 0.1]: stiffness-proportional damping D = beta K,
  /// U + beta dU/dt = C F on the contact nodes (linear model only; 0 = elastic, the paper).
  double damping_time = 0.0;
  LinearSolverSettings solver;
  std::filesystem::path cache_directory; ///< generated meshes; empty: default_mesh_cache()

  /// Declares the entries (with defaults, ranges and help) in the current
  /// subsection of @p prm.
  static void declare(dealii::ParameterHandler& prm);
  /// Reads the entries from the current subsection. Relative paths are
  /// resolved against @p scene_directory, then against the Plantar source
  /// tree. Throws std::invalid_argument naming the parameter, its value and
  /// the allowed range for values the patterns cannot express (e.g. > 0).
  void parse(dealii::ParameterHandler& prm, const std::filesystem::path& scene_directory);

  /// The gmsh request for this sole (numbers SoleLength, ... SoleHex).
  MeshRequest mesh_request() const;
};

/// $PLANTAR_MESH_CACHE, else $XDG_CACHE_HOME/plantar/meshes, else
/// ~/.cache/plantar/meshes.
std::filesystem::path default_mesh_cache();

/// Resolves @p path: absolute as is, else relative to @p scene_directory if
/// it exists there, else relative to the Plantar source tree.
std::filesystem::path resolve_path(const std::filesystem::path& path,
                                   const std::filesystem::path& scene_directory);

} // namespace plantar::fem
