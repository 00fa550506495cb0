#include "apps/progress.h"

#include <algorithm>
#include <cstdio>
#include <unistd.h>
#include <utility>

namespace plantar::app {

bool ProgressBar::terminal() {
  return ::isatty(STDOUT_FILENO) && ::isatty(STDERR_FILENO);
}

ProgressBar::ProgressBar(std::string label, double end_time, bool enabled)
    : label_(std::move(label)), end_time_(end_time), enabled_(enabled),
      start_(std::chrono::steady_clock::now()), last_(start_) {}

void ProgressBar::update(double t) {
  if (!enabled_)
    return;
  const auto now = std::chrono::steady_clock::now();
  if (drawn_ && now - last_ < std::chrono::milliseconds(200) && t < end_time_)
    return;
  last_ = now;
  drawn_ = true;
  const double wall = std::chrono::duration<double>(now - start_).count();
  const double fraction = end_time_ > 0 ? std::clamp(t / end_time_, 0.0, 1.0) : 1.0;
  constexpr int width = 30;
  char bar[width + 1];
  const int filled = static_cast<int>(fraction * width);
  for (int i = 0; i < width; ++i)
    bar[i] = i < filled ? '#' : '.';
  bar[width] = '\0';
  const double factor = wall > 0 ? t / wall : 0;
  const double left = factor > 0 ? (end_time_ - t) / factor : 0;
  std::fprintf(stderr, "\r%s [%s] t = %.3f / %.3f s, real-time factor %.3g, %.0f s left   ",
               label_.c_str(), bar, t, end_time_, factor, left);
  std::fflush(stderr);
}

void ProgressBar::finish() {
  if (enabled_ && drawn_) {
    std::fprintf(stderr, "\r%*s\r", 100, "");
    std::fflush(stderr);
  }
  drawn_ = false;
}

} // namespace plantar::app
