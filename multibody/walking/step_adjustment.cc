#include "multibody/walking/step_adjustment.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

namespace plantar::walking {

void check_step_adjustment_parameters(const StepAdjustmentParameters& p) {
  auto fail = [](const char* name, double value, const char* range) {
    throw std::invalid_argument(std::string("step adjustment: ") + name + " = " +
                                std::to_string(value) + " is outside " + range);
  };
  if (!(p.gain >= 0 && p.gain <= 2))
    fail("gain", p.gain, "[0, 2]");
  if (!(p.max_forward > 0))
    fail("max forward", p.max_forward, "(0, inf) m");
  if (!(p.max_outward >= 0))
    fail("max outward", p.max_outward, "[0, inf) m");
  if (!(p.max_inward >= 0))
    fail("max inward", p.max_inward, "[0, inf) m");
  if (!(p.freeze_time >= 0))
    fail("freeze time", p.freeze_time, "[0, inf) s");
  if (!(p.max_target_speed > 0))
    fail("max target speed", p.max_target_speed, "(0, inf) m/s");
  if (!(p.landing_time_constant > 0))
    fail("landing time constant", p.landing_time_constant, "(0, inf) s");
  if (!(p.leg_iterations >= 0))
    fail("leg iterations", p.leg_iterations, "[0, inf)");
  if (!(p.cop_margin >= 0))
    fail("CoP margin", p.cop_margin, "[0, inf) m");
}

StepAdjustment::StepAdjustment(const StepAdjustmentParameters& parameters)
    : parameters_(parameters) {
  check_step_adjustment_parameters(parameters);
}

void StepAdjustment::update(double t, const std::array<PlannedSwing, 2>& swings,
                            const std::array<Eigen::Matrix2d, 2>& yaw,
                            const std::array<bool, 2>& touched,
                            const std::array<Eigen::Vector2d, 2>& sensed,
                            const Eigen::Vector2d& deficit, double omega, double deficit_scale,
                            double dt) {
  const StepAdjustmentParameters& p = parameters_;
  deficit_ = deficit;
  // A moved landing is where it was sensed, once its foot is down: at its planned touchdown,
  // or on its touchdown when late (or at the next lift-off, if it never reads one).
  auto land = [&](int foot) {
    max_landing_error_ = std::max(max_landing_error_, (landing_ - target_).norm());
    target_ = landing_;
    anchor_[foot] = plan_ = target_;
  };
  const bool lifting =
      (!swinging_[0] && swings[0].progress >= 0) || (!swinging_[1] && swings[1].progress >= 0);
  if (late_ >= 0) {
    if (touched[late_] || lifting) {
      land(late_);
      late_ = -1;
    } else {
      landing_ = sensed[late_];
    }
  }
  // Landings (the planned touchdown has passed), then lift-offs.
  for (int foot = 0; foot < 2; ++foot)
    if (swinging_[foot] && swings[foot].progress < 0) {
      swinging_[foot] = false;
      const double adjustment = (target_ - plan_).norm();
      max_adjustment_ = std::max(max_adjustment_, adjustment);
      adjusted_ += adjustment > 1e-3;
      foot_[foot] = anchor_[foot] = plan_ = target_;
      if (p.enabled && adjustment > 1e-3) {
        if (touched[foot])
          land(foot);
        else
          late_ = foot; // the target until it is down
      }
      if (swing_ == foot)
        swing_ = -1;
    }
  // A landed foot's command relaxes to where it is.
  for (int foot = 0; foot < 2; ++foot)
    if (!swinging_[foot])
      foot_[foot] += (1 - std::exp(-dt / p.landing_time_constant)) * (anchor_[foot] - foot_[foot]);
  for (int foot = 0; foot < 2; ++foot)
    if (!swinging_[foot] && swings[foot].progress >= 0) {
      swinging_[foot] = true;
      swing_ = foot;
      lift_ = foot_[foot];
      target_ = plan_;
      landing_ = sensed[foot];
    }

  if (swing_ < 0) {
    dcm_ = plan_;
  } else {
    const PlannedSwing& s = swings[swing_];
    const double tau = std::max(s.touchdown_time - t, 0.0);
    if (p.enabled && tau > p.freeze_time && !touched[swing_]) {
      const Eigen::Vector2d step =
          target_ - plan_ + p.gain * deficit / deficit_scale * std::exp(omega * tau);
      Eigen::Vector2d local = yaw[swing_].transpose() * step;
      local.x() = std::clamp(local.x(), -p.max_forward, p.max_forward);
      // Right foot (0): outward is -y; left (1): +y.
      const double low = swing_ == 0 ? -p.max_outward : -p.max_inward;
      const double high = swing_ == 0 ? p.max_inward : p.max_outward;
      local.y() = std::clamp(local.y(), low, high);
      const Eigen::Vector2d move = plan_ + yaw[swing_] * local - target_;
      const double limit = p.max_target_speed * dt, length = move.norm();
      target_ += length > limit ? Eigen::Vector2d(move * (limit / length)) : move;
    }
    foot_[swing_] = anchor_[swing_] = lift_ + (target_ - lift_) * std::clamp(s.progress, 0.0, 1.0);
    if (!touched[swing_])
      landing_ = sensed[swing_];
    dcm_ = plan_ + (target_ - plan_) * std::exp(-omega * tau);
  }
  com_ += (1 - std::exp(-omega * dt)) * (dcm_ - com_);
}

} // namespace plantar::walking
