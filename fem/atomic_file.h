#pragma once
// Write-then-rename output, so that an interrupted or failed run never
// leaves a half-written file under the final name.

#include <filesystem>
#include <fstream>
#include <functional>
#include <string>

namespace plantar::fem {

/// Calls @p write on a stream opened on "<path>.tmp-<pid>", then renames the
/// temporary file to @p path. On any exception the temporary file is removed
/// and the exception is rethrown. Throws std::runtime_error naming the file if
/// it cannot be opened or written.
void write_file_atomically(const std::filesystem::path& path,
                           const std::function<void(std::ostream&)>& write);

} // namespace plantar::fem
