#pragma once
// Joint PD control gains, applied implicitly by the Stepper (stepper.h).

#include "multibody/model.h"

#include <Eigen/Core>

namespace plantar::multibody {

/// tau_pd = stiffness (q_ref - q) + damping (v_ref - v), per velocity index (size nv).
/// Entries for the free base and for passive (compliant) joints must be zero.
struct PdGains {
  Eigen::VectorXd stiffness; ///< N m/rad or N/m, >= 0, size nv
  Eigen::VectorXd damping;   ///< N m s/rad or N s/m, >= 0, size nv

  /// Zero gains for @p model.
  static PdGains Zero(const Model& model);
  /// The same gains (kp, kd) on every actuated joint of @p model.
  static PdGains Uniform(const Model& model, double kp, double kd);
  /// Throws std::invalid_argument naming the index, value and allowed range.
  void validate(const Model& model) const;
};

} // namespace plantar::multibody
