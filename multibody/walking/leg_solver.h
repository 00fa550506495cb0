// Inverse kinematics of one leg of a Humanoid: Kajita's closed form where the leg has HRP-2's
// structure (leg_geometry.h), the numerical SE(3) solver (numerical_leg_ik.h) otherwise.
#pragma once

#include "multibody/model.h"
#include "multibody/walking/humanoid.h"
#include "multibody/walking/leg_geometry.h"
#include "multibody/walking/leg_ik.h"
#include "multibody/walking/numerical_leg_ik.h"

#include <Eigen/Core>
#include <Eigen/Geometry>

#include <memory>
#include <optional>
#include <string>

namespace plantar::walking {

/// How a LegSolver solves (Robot/Leg IK).
enum class LegIkMethod {
  automatic, ///< the closed form where the geometry fits, else numerical
  numerical, ///< always the numerical solver
};

class LegSolver {
public:
  /// @p model: the robot without compliant ankles (free base); @p humanoid resolved on it.
  /// Throws std::runtime_error naming the leg if the closed form cannot be used and the
  /// numerical solver cannot be built.
  LegSolver(const multibody::Model& model, const Humanoid& humanoid, LegSide side,
            LegIkMethod method = LegIkMethod::automatic);
  LegSolver(LegSolver&&) noexcept;
  ~LegSolver();

  /// True if the closed form is used; else why_numerical() says why not.
  bool analytic() const { return geometry_.has_value(); }
  const std::string& why_numerical() const { return why_numerical_; }

  /// Leg angles (hip first, Humanoid::leg_joints order) that put the sole frame at @p sole
  /// (world) with the base at @p base (world). @p q: in, the warm start of the numerical solver
  /// (the previous solution); out, the solution. Throws std::runtime_error naming the leg, the
  /// joint and its limits if a joint leaves its limits, or the pose if it is out of reach.
  void solve(const Eigen::Isometry3d& base, const Eigen::Isometry3d& sole, LegAngles& q);

  /// Sole pose (world) of leg angles @p q with the base at @p base (forward kinematics).
  Eigen::Isometry3d sole_pose(const Eigen::Isometry3d& base, const LegAngles& q);

private:
  void set_configuration(const Eigen::Isometry3d& base, const LegAngles& q);

  const multibody::Model* model_;
  LegSide side_;
  std::array<int, 6> joints_{};
  int sole_frame_ = 0;
  std::optional<LegGeometry> geometry_;
  std::string why_numerical_;
  std::unique_ptr<NumericalLegIk> numerical_;
  multibody::Data data_;
  Eigen::VectorXd q_full_;
};

} // namespace plantar::walking
