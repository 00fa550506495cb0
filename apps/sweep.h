#pragma once
// `plantar sweep`: one run of a scene per grid point (foot form x time step x, for the FEM
// sole, Young's modulus x Poisson ratio x relaxation time, times the general axes Sweep/Axis N,
// each any scene entry; subsection Sweep), each in its own child
// process `plantar run DIR/points/<id>/scene.prm -o DIR/points/<id>`, up to N at a time. A point is
// finished when its DIR/points/<id>/summary.csv (or failure.txt) exists; both are written
// atomically, so an interrupted sweep resumes without recomputing finished points.
// The results are gathered into DIR/sweep.csv (one row per point). Under mpirun the points are
// spread over the ranks (apps/sweep_queue.h, docs/cluster.md).

#include "apps/scene.h"

#include <filesystem>
#include <string>
#include <vector>

namespace plantar::app {

struct SweepPoint {
  FootForm form = FootForm::fem_sole;
  double time_step = 0;      ///< s
  double youngs_modulus = 0; ///< Pa; 0: the scene's material (or not an FEM sole)
  double poisson_ratio = 0;  ///< valid if youngs_modulus or has_poisson_ratio
  bool has_poisson_ratio = false;
  double relaxation_time = 0; ///< s, tau1 of a law=prony sole; 0: the scene's material
  /// The value index of each general axis (Sweep/Axis N, scene.sweep.axes order).
  std::vector<std::size_t> axis_values;
  std::string id; ///< directory name, e.g. fem_sole_dt1ms_E4MPa_nu0.3
};

/// The grid of @p scene: forms (Robot/Foot forms, or Robot/Foot form) x Sweep/Time steps (or
/// Simulation/Time step) x, for fem sole, Sweep/Young's moduli x Sweep/Poisson ratios x
/// Sweep/Relaxation times, times every general axis (the last varying fastest; each adds
/// "_<tag>" to the id, SweepAxis::tag).
std::vector<SweepPoint> sweep_points(const Scene& scene);

/// Sole/Materials @p materials with every "E=..." replaced by @p youngs_modulus (if > 0) and
/// every "nu=..." by @p poisson_ratio (if @p set_nu) and every "tau1=..." by
/// @p relaxation_time (s, if > 0). Throws std::invalid_argument naming Sweep/Relaxation times if
/// a relaxation time is given but the materials have no tau1 (not a viscoelastic sole).
std::string replace_material(const std::string& materials, double youngs_modulus,
                             double poisson_ratio, bool set_nu, double relaxation_time = 0);

/// Runs the sweep of @p scene_file (already loaded into @p scene) into @p output with up to
/// @p jobs child processes of @p executable (the plantar binary); called on rank 0 only when
/// MPI runs several ranks (the others run run_sweep_worker), @p jobs then per rank. Writes
/// output/{parameters.prm, sweep.csv, summary.txt}. Returns 0 if every point succeeded, 1
/// otherwise (the failed points are listed with their messages).
int run_sweep(const std::filesystem::path& scene_file, const Scene& scene,
              const std::filesystem::path& output, int jobs,
              const std::filesystem::path& executable);

} // namespace plantar::app
