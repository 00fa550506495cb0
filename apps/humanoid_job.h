#pragma once
// Running a humanoid scene (stand, drop, lean, walk) from `plantar run`: simulate, write the
// CSV time series and return the summary text.

#include "apps/humanoid_simulation.h"
#include "apps/scene.h"

#include <filesystem>
#include <string>

namespace plantar::app {

/// Runs @p scene to its end, writes <output>/{waist,joints,contacts}.csv (if Output/Write CSV)
/// and returns the summary. On a numerical failure the CSV of the steps done so far are
/// written to <output>/failed/ and the std::runtime_error (step, time, cause) is rethrown.
/// A progress bar (apps/progress.h) shows the simulated time when stdout and stderr are
/// terminals.
HumanoidSummary run_humanoid(const Scene& scene, const std::filesystem::path& output);

/// The comparison of foot forms (Robot/Foot forms non-empty): runs @p scene once per form
/// into output/<form_directory>/ (parameters.prm, summary.txt, summary.csv, CSV; a failed
/// form: failure.txt and its CSV up to the failure in failed/), prints each summary, writes
/// output/summary.txt and, if @p figures, the figures (plot_directory). Returns 0 if every
/// form ran to its end, 1 otherwise (the failed forms listed with their messages).
int run_comparison(const std::filesystem::path& scene_file, const Scene& scene,
                   const std::filesystem::path& output, bool figures = true);

/// Directory name of a foot form in a comparison: rigid, compliant_ankle, fem_sole.
std::string form_directory(FootForm form);

/// Writes @p summary as "name,value" lines (17 digits) to @p path atomically: the figures read
/// back by `plantar sweep` and the plot script (max_waist_acceleration_z in m/s^2,
/// roll_difference_deg = commanded - measured final roll in deg, solver statistics, ...).
void write_summary_csv(const std::filesystem::path& path, const HumanoidSummary& summary);

/// Reads a file written by write_summary_csv; throws std::runtime_error naming the file if it
/// lacks @p name.
double read_summary_value(const std::filesystem::path& path, const std::string& name);

/// Runs `/usr/bin/python3 apps/plot/plantar_plot.py DIR`: PNG figures from the CSVs under
/// @p directory into @p directory/figures/. Returns the script's exit status (its messages go
/// to stderr).
int plot_directory(const std::filesystem::path& directory);

/// The figures of @p summary as human-readable lines.
std::string format_summary(const Scene& scene, const HumanoidSummary& summary);

} // namespace plantar::app
