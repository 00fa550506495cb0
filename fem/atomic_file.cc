#include "fem/atomic_file.h"

#include <stdexcept>
#include <unistd.h>

namespace plantar::fem {

void write_file_atomically(const std::filesystem::path& path,
                           const std::function<void(std::ostream&)>& write) {
  if (path.has_parent_path())
    std::filesystem::create_directories(path.parent_path());
  const std::filesystem::path tmp = path.string() + ".tmp-" + std::to_string(::getpid());
  try {
    {
      std::ofstream out(tmp, std::ios::binary);
      if (!out)
        throw std::runtime_error("cannot open '" + tmp.string() + "' for writing");
      write(out);
      out.flush();
      if (!out)
        throw std::runtime_error("failed while writing '" + tmp.string() + "'");
    }
    std::filesystem::rename(tmp, path);
  } catch (...) {
    std::error_code ignored;
    std::filesystem::remove(tmp, ignored);
    throw;
  }
}

} // namespace plantar::fem
