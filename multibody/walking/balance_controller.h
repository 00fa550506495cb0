#pragma once
// The sensor-based balance loop of a humanoid, called once per control period before the PD
// step: sensors (multibody/sensors/robot_sensors.h) -> CoM/DCM estimate (com_estimator.h, or
// the ground truth when asked) -> DCM stabilizer (dcm_stabilizer.h) -> joint references.
// The reference's own DCM and ZMP come from the reference configuration q_ref:
//   c_ref = CoM(q_ref),  c_ref' = (c_ref,n - c_ref,n-1) / dt,  xi_ref = c_ref + c_ref' / omega,
//   p_ref = xi_ref - xi_ref' / omega, low-passed with time constant T_p (the finite
//   difference of an interpolated reference is rough).
// A foot is in contact when its reference sole is within contact_height of its height at
// t = 0 plus the change of its planned ground height (set_planned_ground; 0 on flat ground) and
// its F/T sensor reads more than the stabilizer's min_contact_force.
// With touchdown adaptation on, each foot's height offset dz (touchdown_adaptation.h) moves its
// reference sole (the contact test, the estimator's anchors and the leg offsets below).
// With step adjustment on (step_adjustment.h; its deficit is the excess of c + xi - xi_ref over
// the stance sole's rectangle, c the sole's centre, xi - xi_ref the estimated DCM error; the plan's
// swings from set_planned_swings), the reference DCM and ZMP are translated by its shifts dxi and
// dp, each reference sole by its anchor shift (the stabilizer's feet, the estimator's
// anchors; the sensed landing, step_adjustment.h), each leg by its foot shift w_i and the
// waist by the CoM shift dc.
// With step timing on (step_timing.h; the same deficit and DCM error, v = omega (xi_ref -
// p_ref) translated as above), the caller plays the reference at the rate step_timing().rate()
// (its times in set_planned_swings are reference times); c_ref' stays the finite difference
// over dt, the reference as played: xi_ref = c + r dc/dt_ref / omega, and p_ref holds the
// reference's acceleration r^2 d2c/dt_ref^2 + r' dc/dt_ref.
// Foot offsets become joint references through each leg's Jacobian at q_ref (sole frame,
// world-aligned axes, the leg's 6 joints): dq_leg = J_leg^-1 [w_i - dc, z, R_sole (roll,
// pitch, 0)], z the force difference offset plus dz, added to q_ref's leg joints; with step
// adjustment on, StepAdjustmentParameters::leg_iterations Newton steps then bring each sole to
// that offset pose (the linearisation errs by centimetres at a decimetre's shift). Allocates
// nothing after construction.

#include "multibody/data.h"
#include "multibody/model.h"
#include "multibody/sensors/robot_sensors.h"
#include "multibody/spatial.h"
#include "multibody/walking/com_estimator.h"
#include "multibody/walking/dcm_stabilizer.h"
#include "multibody/walking/humanoid.h"
#include "multibody/walking/step_adjustment.h"
#include "multibody/walking/step_timing.h"
#include "multibody/walking/touchdown_adaptation.h"

#include <Eigen/Core>
#include <Eigen/LU>

#include <array>

namespace plantar::walking {

/// Where the CoM and DCM fed back come from.
enum class StateEstimate {
  kinematic,    ///< encoders + IMU + F/T anchoring (com_estimator.h)
  ground_truth, ///< the simulator's state (for comparison only)
};

struct BalanceParameters {
  multibody::sensors::RobotSensorParameters sensors;
  StateEstimate estimate = StateEstimate::kinematic;
  ComEstimatorParameters estimator;
  DcmStabilizerParameters stabilizer; ///< its omega is set from the reference's CoM height
  double zmp_time_constant = 0.02;    ///< T_p, s, > 0
  double contact_height = 0.002;      ///< m, > 0
  /// Early and late touchdowns (touchdown_adaptation.h).
  TouchdownParameters touchdown;
  /// Where the swing foot lands (step_adjustment.h).
  StepAdjustmentParameters step;
  /// When the swing foot lands (step_timing.h).
  StepTimingParameters timing;
};

/// Running figures of the loop (for summaries and tests).
struct BalanceStatistics {
  double max_dcm_error = 0;                            ///< m, max |xi_est - xi_ref| (horizontal)
  double max_com_estimate_error = 0;                   ///< m, max |c_est - c_true|
  double max_dcm_estimate_error = 0;                   ///< m, max |xi_est - xi_true| (horizontal)
  double max_true_dcm_error = 0;                       ///< m, max |xi_true - xi_ref| (horizontal)
  Eigen::Vector2d dcm_error = Eigen::Vector2d::Zero(); ///< last xi_est - xi_ref
  Eigen::Vector2d true_dcm_error = Eigen::Vector2d::Zero(); ///< last xi_true - xi_ref
};

class BalanceController {
public:
  /// @p model (outlives this) and @p humanoid resolved on it; @p dt the control period (s).
  BalanceController(const multibody::Model& model, const Humanoid& humanoid,
                    const BalanceParameters& parameters, double dt, bool stabilize);
  /// One control period at the state (q, v) with generalized acceleration @p a (nv) and the
  /// ground's wrench on each foot ([f; n] about the world origin, world axes): measures,
  /// estimates and, when stabilizing, adds the leg offsets to @p q_ref (nq, modified in place).
  void update(const Eigen::Ref<const Eigen::VectorXd>& q,
              const Eigen::Ref<const Eigen::VectorXd>& v,
              const Eigen::Ref<const Eigen::VectorXd>& a,
              const std::array<multibody::Vector6d, 2>& ground_wrenches,
              Eigen::Ref<Eigen::VectorXd> q_ref);
  /// The planned ground height under each sole (right, left) [m] for the next update
  /// (JointReference::ground_at); its change since the first update shifts the contact test.
  void set_planned_ground(const Eigen::Vector2d& heights) { planned_ground_ = heights; }
  /// The planned support polygon of each sole (right, left; JointReference::support_at, sole
  /// frame; nullptr: the sole's rectangle) for the next update; they must outlive it.
  void set_planned_supports(const Eigen::Matrix2Xd* right, const Eigen::Matrix2Xd* left) {
    feet_[0].support = right;
    feet_[1].support = left;
  }
  /// Each sole's planned swing at the time of the next update (JointReference::swing_at) and
  /// that time @p t (s).
  void set_planned_swings(const std::array<PlannedSwing, 2>& swings, double t) {
    swings_ = swings;
    swing_time_ = t;
  }
  const BalanceStatistics& statistics() const { return statistics_; }
  const ComEstimator& estimator() const { return estimator_; }
  const DcmStabilizer& stabilizer() const { return stabilizer_; }
  const TouchdownAdaptation& touchdown() const { return touchdown_; }
  const StepAdjustment& step_adjustment() const { return step_; }
  /// The reference's rate r for the next period and its advance t_ref - t (step_timing.h).
  const StepTiming& step_timing() const { return timing_; }
  double omega() const { return omega_; }
  /// xi_ref (x, y; m), translated by the step adjustment's dxi
  const Eigen::Vector2d& reference_dcm() const { return dcm_target_; }
  /// p_ref (filtered; x, y; m), translated by dp
  const Eigen::Vector2d& reference_zmp() const { return zmp_target_; }

private:
  const multibody::Model& model_;
  const Humanoid& humanoid_;
  BalanceParameters parameters_;
  double dt_, omega_ = 0;
  bool stabilize_;
  multibody::sensors::RobotSensors sensors_;
  ComEstimator estimator_;
  DcmStabilizer stabilizer_;
  TouchdownAdaptation touchdown_;
  StepAdjustment step_;
  StepTiming timing_;
  std::array<PlannedSwing, 2> swings_{};
  double swing_time_ = 0;
  multibody::Data reference_data_, true_data_, leg_data_;
  std::array<multibody::SE3, 2> sole_targets_;     ///< reference soles with their offsets
  std::array<Eigen::Vector3d, 2> reference_soles_; ///< the reference's soles (world, m)
  std::array<multibody::SE3, 2> sensor_in_sole_;   ///< F/T sensor frame -> sole frame
  std::array<double, 2> ground_height_{};
  Eigen::Vector2d planned_ground_ = Eigen::Vector2d::Zero(),
                  planned_ground0_ = Eigen::Vector2d::Zero();
  bool first_ = true;
  Eigen::Vector3d com_ref_ = Eigen::Vector3d::Zero();
  Eigen::Vector2d dcm_ref_ = Eigen::Vector2d::Zero(), zmp_ref_ = Eigen::Vector2d::Zero();
  Eigen::Vector2d dcm_target_ = Eigen::Vector2d::Zero(), zmp_target_ = Eigen::Vector2d::Zero();
  std::array<StabilizerFoot, 2> feet_{};
  Eigen::Matrix<double, 6, Eigen::Dynamic> jacobian_;
  multibody::Matrix6d leg_jacobian_;
  Eigen::PartialPivLU<multibody::Matrix6d> leg_lu_;
  BalanceStatistics statistics_;
};

} // namespace plantar::walking
