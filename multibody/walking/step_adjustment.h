#pragma once
// Step adjustment: where the ankle strategy (dcm_stabilizer.h) cannot bring the DCM back, the
// swing foot lands elsewhere and the rest of the walk is translated with it (the capture-point
// step strategy of Pratt et al. 2006 and Englsberger et al. 2011, on the linear inverted
// pendulum xi' = omega (xi - p)).
//   The plan's shift S (m, world x, y): every placement not yet reached is translated by S;
//   a swing's landing target S_t starts at S at lift-off. With the error e = xi - xi_ref,
//   e' = omega (e - (p - p_ref)): the ankle alone brings e back while p_ref + e lies in the
//   stance sole's CoP region, and no ZMP there can for the excess d of p_ref + e over it. The
//   balance loop gives d in single support (the excess of c + e over the sole's rectangle
//   shrunk by cop_margin, c: the sole centre, for p_ref, which lags the transfer at lift-off),
//   in DCM units; a caller with another deficit passes its ratio s to
//   the DCM excess (e.g. 1 + k_p / omega for the desired ZMP's excess). Translating the landing
//   by dS moves the reference DCM by dS exp(-omega tau) now (tau: time to the planned
//   touchdown), so each period
//     S_t <- S + clamp(S_t - S + k_s (d / s) exp(omega tau))
//   (clamp: the landing's own axes, forward +-max_forward, sideways max_outward away from the
//   stance foot and max_inward towards it; S_t moving at most max_target_speed dt per period),
//   held for the last freeze_time of the swing and once the swing foot reads a touchdown.
//   The swing foot is commanded (its leg, relative to the waist) along
//     w_swing = w_lift + (S_t - w_lift) s   (s: the swing's planned horizontal progress).
//   A moved foot (|S_t - S| > 1 mm) lands where the body puts it: the sensed landing m (the sole's
//   offset from its plan by the kinematics from the stance sole, taken while the swing foot is
//   unloaded) becomes the plan's shift at the planned touchdown, S <- m, and the foot's anchor
//   (where the estimator and the stabilizer take it to be); its command relaxes from S_t to m with
//   the time constant landing_time_constant while it is down (the waist moves back under the plan).
//   A foot still unloaded at its planned touchdown (a late touchdown) is taken at its target,
//   S <- S_t, until its sensor reads the touchdown (or the next swing lifts off), then S <- m.
//   The reference's ZMP, DCM and CoM are translated by
//     dp = S,  dxi = S + (S_t - S) exp(-omega tau) (S out of a swing),  dc' = omega (dxi - dc)
//   (the bounded LIPM solution for the translated ZMP reference; dc exact per period).
// Allocates nothing.

#include <Eigen/Core>

#include <array>

namespace plantar::walking {

struct StepAdjustmentParameters {
  bool enabled = false;     ///< off: the shifts stay 0
  double gain = 1;          ///< k_s, [0, 2]: 1 removes the ankle's excess DCM error
  double max_forward = 0.1; ///< m, > 0: |adjustment| along the landing sole's x axis
  double max_outward = 0.1; ///< m, >= 0: sideways, away from the stance foot
  double max_inward = 0.02; ///< m, >= 0: sideways, towards the stance foot
  double freeze_time = 0.1; ///< s, >= 0: before the planned touchdown the target is held
  /// m, >= 0: the DCM deficit is taken against the stance sole's CoP region shrunk by this
  /// further (the balance loop); 0: the LIPM's exact bound of what the ankle can take
  double cop_margin = 0;
  /// m/s, > 0: the landing target moves at most this fast (an estimate's spike moves it little)
  double max_target_speed = 1.0;
  /// Newton steps of the legs to their offset soles (the balance loop), >= 0
  int leg_iterations = 2;
  /// s, > 0: a landed foot's command relaxes to its sensed landing
  double landing_time_constant = 0.2;
};

/// Throws std::invalid_argument naming the parameter, its value and the allowed range.
void check_step_adjustment_parameters(const StepAdjustmentParameters& parameters);

/// One sole's planned swing (JointReference::swing_at): progress in [0, 1] and planned
/// touchdown time [s]; progress < 0 while the sole is down.
struct PlannedSwing {
  double progress = -1;
  double touchdown_time = -1;
};

class StepAdjustment {
public:
  explicit StepAdjustment(const StepAdjustmentParameters& parameters = {});
  /// One control period ending at time @p t (s) of length @p dt (s).
  /// @param swings each sole's (right, left) planned swing
  /// @param yaw each reference sole's horizontal axes (2 x 2, world <- sole)
  /// @param touched each sole's F/T sensor reads a touchdown
  /// @param sensed each sole's offset from its plan as sensed (world x, y; m)
  /// @param deficit the deficit d (world x, y; m)
  /// @param omega sqrt(g / z_c), 1/s; @param deficit_scale s, d over the DCM excess (> 0; 1: d
  /// is the DCM excess)
  void update(double t, const std::array<PlannedSwing, 2>& swings,
              const std::array<Eigen::Matrix2d, 2>& yaw, const std::array<bool, 2>& touched,
              const std::array<Eigen::Vector2d, 2>& sensed, const Eigen::Vector2d& deficit,
              double omega, double deficit_scale, double dt);
  /// w_i: where sole i's (0 right, 1 left) leg is asked to put it, relative to its plan
  /// (world x, y; m).
  const Eigen::Vector2d& foot_shift(int foot) const { return foot_[foot]; }
  /// Where sole i is taken to be relative to its plan: its sensed landing (its command while it
  /// swings; world x, y; m).
  const Eigen::Vector2d& anchor_shift(int foot) const { return anchor_[foot]; }
  const Eigen::Vector2d& plan_shift() const { return plan_; }       ///< S, m
  const Eigen::Vector2d& landing_target() const { return target_; } ///< S_t (S out of a swing)
  const Eigen::Vector2d& zmp_shift() const { return plan_; }        ///< dp, m
  const Eigen::Vector2d& dcm_shift() const { return dcm_; }         ///< dxi, m
  const Eigen::Vector2d& com_shift() const { return com_; }         ///< dc, m
  const Eigen::Vector2d& deficit() const { return deficit_; }       ///< the last d, m
  int adjusted_steps() const { return adjusted_; }          ///< landings with |S_t - S| > 1 mm
  double max_adjustment() const { return max_adjustment_; } ///< max |S_t - S| at landing, m
  /// max |m - S_t| at landing, m: how far the body put a foot from its target
  double max_landing_error() const { return max_landing_error_; }

private:
  StepAdjustmentParameters parameters_;
  std::array<Eigen::Vector2d, 2> foot_{Eigen::Vector2d::Zero(), Eigen::Vector2d::Zero()};
  std::array<Eigen::Vector2d, 2> anchor_{Eigen::Vector2d::Zero(), Eigen::Vector2d::Zero()};
  Eigen::Vector2d landing_ = Eigen::Vector2d::Zero(); ///< m, the swing sole's sensed offset
  Eigen::Vector2d lift_ = Eigen::Vector2d::Zero(), plan_ = Eigen::Vector2d::Zero(),
                  target_ = Eigen::Vector2d::Zero(), dcm_ = Eigen::Vector2d::Zero(),
                  com_ = Eigen::Vector2d::Zero(), deficit_ = Eigen::Vector2d::Zero();
  std::array<bool, 2> swinging_{false, false};
  int swing_ = -1;
  int late_ = -1; ///< a moved foot past its planned touchdown, not yet down
  int adjusted_ = 0;
  double max_adjustment_ = 0, max_landing_error_ = 0;
};

} // namespace plantar::walking
