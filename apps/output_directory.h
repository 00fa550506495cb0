#pragma once
// The output directory of a run: what a new run removes before it writes, so that a directory
// reused after a killed or failed run never mixes two runs' outputs.

#include <filesystem>

namespace plantar::app {

/// Removes from @p directory, if it exists, (not from its subdirectories, except the two named)
/// what an earlier run left that the new one would not overwrite as a whole: first the marks of
/// a finished run (summary.csv, which `plantar sweep` takes for a finished point, summary.txt,
/// failure.txt), then the steps of a failed run (failed/), the ParaView series (vtk/ and *.pvd,
/// whose frame counts may differ) and the temporary files of killed runs (*.tmp-<pid>,
/// fem/atomic_file.h). Other files are kept (parameters.prm, the CSVs and log.txt are
/// rewritten whole by the new run).
void prepare_output_directory(const std::filesystem::path& directory);

} // namespace plantar::app
