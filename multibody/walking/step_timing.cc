#include "multibody/walking/step_timing.h"

#include <algorithm>
#include <stdexcept>
#include <string>

namespace plantar::walking {

void check_step_timing_parameters(const StepTimingParameters& p) {
  auto fail = [](const char* name, double value, const char* range) {
    throw std::invalid_argument(std::string("step timing: ") + name + " = " +
                                std::to_string(value) + " is outside " + range);
  };
  if (!(p.time_constant > 0))
    fail("time constant", p.time_constant, "(0, inf) s");
  if (!(p.max_rate >= 1))
    fail("max rate", p.max_rate, "[1, inf)");
  if (!(p.freeze_time >= 0))
    fail("freeze time", p.freeze_time, "[0, inf) s");
}

StepTiming::StepTiming(const StepTimingParameters& parameters) : parameters_(parameters) {
  check_step_timing_parameters(parameters);
}

void StepTiming::update(double t_ref, const std::array<PlannedSwing, 2>& swings,
                        const std::array<bool, 2>& touched, const Eigen::Vector2d& error,
                        const Eigen::Vector2d& deficit, const Eigen::Vector2d& dcm_velocity,
                        double dt) {
  const bool right = swings[0].progress >= 0, left = swings[1].progress >= 0;
  const int swing = right != left ? (right ? 0 : 1) : -1;
  if (swing != swing_)
    counted_ = false;
  swing_ = swing;
  lead_ = 0;
  rate_ = 1;
  if (!parameters_.enabled || swing < 0 || touched[swing] ||
      swings[swing].touchdown_time - t_ref <= parameters_.freeze_time)
    return;
  const double speed2 = dcm_velocity.squaredNorm();
  if (!(speed2 > 1e-12) || !(deficit.dot(dcm_velocity) > 0))
    return;
  lead_ = std::max(error.dot(dcm_velocity), 0.0) / speed2;
  rate_ = std::min(1 + lead_ / parameters_.time_constant, parameters_.max_rate);
  max_rate_ = std::max(max_rate_, rate_);
  advance_ += (rate_ - 1) * dt;
  if (rate_ > 1 && !counted_) {
    ++shortened_;
    counted_ = true;
  }
}

} // namespace plantar::walking
