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
HumanoidSummary run_humanoid(const Scene& scene, const std::filesystem::path& output);

/// The figures of @p summary as human-readable lines.
std::string format_summary(const Scene& scene, const HumanoidSummary& summary);

} // namespace plantar::app
