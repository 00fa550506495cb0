#pragma once
// Step timing: where the ankle strategy cannot bring the DCM back, the walk's reference runs
// faster, so the swing foot lands earlier and the reference catches up with a robot that falls
// ahead of it (the timing half of the step strategy: Khadiv et al. 2016, Griffin et al. 2017,
// here as a time warp of the whole reference on the linear inverted pendulum).
//   The reference is played at its own time t_ref, t_ref' = r (r: the rate, 1 for the plan).
//   With the DCM error e = xi - xi_ref (m), the step adjustment's deficit d (step_adjustment.h:
//   the part of e the stance sole's CoP region cannot take; m) and the reference DCM's velocity
//   v (m/s, as played: the balance loop's omega (xi_ref - p_ref)), moving the reference ahead by
//   the lead
//     lambda = max(e . v, 0) / |v|^2   (s)
//   moves its DCM onto e's component along v (the reference's phase nearest the robot's DCM,
//   to first order). Each period, while one sole swings, its planned touchdown is more than
//   freeze_time ahead (reference time), its F/T sensor reads no touchdown and d . v > 0 (the
//   ankle cannot take the error and it lies along the reference's motion),
//     r = min(1 + lambda / T_t, r_max)   (T_t: time_constant),
//   otherwise r = 1: double support; the last freeze_time of a swing, so the foot's vertical
//   approach keeps its planned touchdown velocity; an error the ankle can take (the walk's
//   timing is the plan's while the ankle strategy suffices); a deficit against the reference's
//   motion (behind it, or outward over the stance foot), which no earlier landing helps.
//   Once e is inside what the ankle can take (d = 0), the ankle strategy brings it back.
// Allocates nothing.

#include "multibody/walking/step_adjustment.h"

#include <Eigen/Core>

#include <array>

namespace plantar::walking {

struct StepTimingParameters {
  bool enabled = false;       ///< off: r = 1
  double time_constant = 0.1; ///< T_t, s, > 0: the lead lambda is removed over about T_t
  double max_rate = 2;        ///< r_max, >= 1: the reference runs at most this fast
  double freeze_time = 0.1;   ///< s, >= 0: before the planned touchdown r = 1
};

/// Throws std::invalid_argument naming the parameter, its value and the allowed range.
void check_step_timing_parameters(const StepTimingParameters& parameters);

class StepTiming {
public:
  explicit StepTiming(const StepTimingParameters& parameters = {});
  /// One control period at reference time @p t_ref (s) of length @p dt (s): the rate for the
  /// next period.
  /// @param swings each sole's (right, left) planned swing, its touchdown in reference time
  /// @param touched each sole's F/T sensor reads a touchdown
  /// @param error e (world x, y; m)
  /// @param deficit d (world x, y; m)
  /// @param dcm_velocity v, the reference DCM's velocity as played (world x, y; m/s)
  void update(double t_ref, const std::array<PlannedSwing, 2>& swings,
              const std::array<bool, 2>& touched, const Eigen::Vector2d& error,
              const Eigen::Vector2d& deficit, const Eigen::Vector2d& dcm_velocity, double dt);
  double rate() const { return rate_; } ///< r for the next period
  double lead() const { return lead_; } ///< the last lambda, s
  /// t_ref - t at the end of the next period (the rates returned so far, r - 1 times dt), s
  double advance() const { return advance_; }
  double max_rate() const { return max_rate_; }       ///< the largest r so far
  int shortened_swings() const { return shortened_; } ///< swings with r > 1 at some period

private:
  StepTimingParameters parameters_;
  double rate_ = 1, lead_ = 0, advance_ = 0, max_rate_ = 1;
  int shortened_ = 0;
  int swing_ = -1;       ///< the sole swinging, -1 in double support
  bool counted_ = false; ///< this swing is in shortened_
};

} // namespace plantar::walking
