#include "apps/landing_detector.h"

#include "apps/time_series.h"

#include <algorithm>
#include <cmath>
#include <sstream>
#include <stdexcept>

namespace plantar::app {

LandingDetector::LandingDetector(const LandingParameters& params, double period, int max_samples)
    : params_(params), period_(period) {
  const auto require = [](bool ok, const char* name, double value, const char* range) {
    if (!ok) {
      std::ostringstream msg;
      msg << "LandingDetector: " << name << " = " << value << " is outside " << range;
      throw std::invalid_argument(msg.str());
    }
  };
  require(params.threshold > 0 && std::isfinite(params.threshold), "threshold", params.threshold,
          "(0, inf) N");
  require(params.window > 0 && params.window <= 10, "window", params.window, "(0, 10] s");
  require(period > 0 && std::isfinite(period), "period", period, "(0, inf) s");
  require(max_samples >= 0, "max_samples", max_samples, "[0, inf)");
  const int capacity = static_cast<int>(std::ceil(params.window / period)) + 3;
  times_.resize(capacity);
  forces_.resize(capacity);
  landings_.reserve(max_samples / 2 + 1);
}

void LandingDetector::update(double t, double force_z, double acceleration) {
  const bool above = force_z >= params_.threshold;
  if (state_ == State::window) {
    times_[n_buffer_] = t;
    forces_[n_buffer_] = force_z;
    ++n_buffer_;
    current_.impulse += force_z * period_;
    current_.peak_acceleration = std::max(current_.peak_acceleration, std::abs(acceleration));
    if (force_z > current_.peak_force) {
      current_.peak_force = force_z;
      current_.peak_time = t;
    }
    current_.window = t - current_.time;
  } else if (state_ == State::armed && above &&
             landings_.size() < landings_.capacity()) { // touchdown
    current_ = Landing();
    current_.time = t_previous_ +
                    (params_.threshold - f_previous_) / (force_z - f_previous_) * (t - t_previous_);
    current_.impulse = force_z * period_;
    current_.peak_force = force_z;
    current_.peak_time = t;
    current_.peak_acceleration = std::abs(acceleration);
    current_.window = t - current_.time;
    times_[0] = t_previous_;
    forces_[0] = f_previous_;
    times_[1] = t;
    forces_[1] = force_z;
    n_buffer_ = 2;
    state_ = State::window;
  } else if (state_ == State::armed && above) {
    state_ = State::loaded; // no room left (cannot happen within max_samples)
  }
  // The next sample would fall past the window (or the buffer is full): close it.
  if (state_ == State::window && (t + period_ > current_.time + params_.window + 1e-9 * period_ ||
                                  n_buffer_ == static_cast<int>(times_.size())))
    close_window();
  if (state_ != State::window && !above)
    state_ = State::armed;
  t_previous_ = t;
  f_previous_ = force_z;
}

double LandingDetector::crossing(double level) const {
  if (forces_[0] >= level)
    return times_[0];
  for (int i = 1; i < n_buffer_; ++i)
    if (forces_[i] >= level)
      return times_[i - 1] +
             (level - forces_[i - 1]) / (forces_[i] - forces_[i - 1]) * (times_[i] - times_[i - 1]);
  return times_[n_buffer_ - 1];
}

void LandingDetector::close_window() {
  current_.rise_time = crossing(0.9 * current_.peak_force) - crossing(0.1 * current_.peak_force);
  landings_.push_back(current_);
  state_ = State::loaded;
}

void LandingDetector::finish() {
  if (state_ == State::window)
    close_window();
}

void write_landings_csv(const std::vector<Landing>& right, const std::vector<Landing>& left,
                        const std::filesystem::path& path) {
  TimeSeries table({"foot", "t", "impulse", "peak_force", "peak_time", "rise_time",
                    "peak_az_filtered", "window"},
                   static_cast<int>(right.size() + left.size()));
  std::size_t i = 0, j = 0;
  while (i < right.size() || j < left.size()) {
    const bool take_right = j == left.size() || (i < right.size() && right[i].time <= left[j].time);
    const Landing& l = take_right ? right[i++] : left[j++];
    auto row = table.append();
    row << (take_right ? 0.0 : 1.0), l.time, l.impulse, l.peak_force, l.peak_time, l.rise_time,
        l.peak_acceleration, l.window;
  }
  table.write_csv(path);
}

} // namespace plantar::app
