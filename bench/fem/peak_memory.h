#pragma once
// Peak resident memory of this process (bench programs).

#include <sys/resource.h>

namespace plantar::bench {

/// Peak resident set size, MB (getrusage's ru_maxrss, kB on Linux).
inline double peak_megabytes() {
  rusage usage{};
  getrusage(RUSAGE_SELF, &usage);
  return usage.ru_maxrss / 1024.0;
}

} // namespace plantar::bench
