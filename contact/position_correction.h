#pragma once
// Normal bias b_k of the Signorini condition v_n + b_k >= 0 (contact_problem.h):
// Newton restitution (paper eq. 5) and a position correction against drift.

namespace plantar::contact {

struct NormalBiasParameters {
  /// Newton restitution e: v_n^+ >= -e v_n^- (eq. 5). Range [0, 1]. Default 0 (plastic impact).
  double restitution = 0.0;
  /// No bounce when |v_n^-| is below this (m/s); avoids micro-bouncing at rest. Range [0, inf).
  double restitution_threshold = 0.0;
  /// Fraction of a penetration removed per step. Range (0, 1]. Default 0.2.
  double position_correction = 0.2;
  /// Penetration tolerated without correction (m). Range [0, inf). Default 0.
  double penetration_slop = 0.0;

  /// Throws std::invalid_argument naming the field, value and range.
  void validate() const;
};

/// Normal bias b (m/s) of v_n^+ + b >= 0, with e_eff = e if |v_n^-| >=
/// restitution_threshold, else 0, and c = beta min(gap + slop, 0) / dt <= 0:
///   impact with bounce (e_eff > 0, v_n^- < 0): b = min(e_eff v_n^-, c)
///       -> v_n^+ >= -e v_n^- (eq. 5), or the correction if stronger;
///   otherwise, gap > 0 (contact active before touching): b = gap / dt
///       -> the body may close the gap within the step but not cross it
///          (lands exactly, no hovering);
///   otherwise (touching or penetrating): b = c
///       -> a penetration gap < -slop shrinks by the factor (1 - beta) per
///          step (Baumgarte-type velocity correction: the push-out velocity
///          stays in the body, which then lifts by up to about the depth).
/// @param gap signed normal gap (m), negative in penetration.
/// @param normal_velocity_before v_n^- at the start of the step (m/s).
/// @param dt time step (s), > 0.
double normal_bias(double gap, double normal_velocity_before, double dt,
                   const NormalBiasParameters& parameters);

} // namespace plantar::contact
