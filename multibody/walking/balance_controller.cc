#include "multibody/walking/balance_controller.h"

#include "multibody/center_of_mass.h"
#include "multibody/jacobian.h"
#include "multibody/kinematics.h"

#include <cmath>
#include <stdexcept>

namespace plantar::walking {
namespace {

/// omega of the reference at q: sqrt(g / (c_z - mean sole height)).
double reference_omega(const multibody::Model& model, const Humanoid& humanoid,
                       multibody::Data& data, const Eigen::Ref<const Eigen::VectorXd>& q) {
  multibody::forward_kinematics(model, data, q);
  const double ground =
      0.5 * (multibody::frame_placement(model, data, humanoid.sole_frames[0]).translation.z() +
             multibody::frame_placement(model, data, humanoid.sole_frames[1]).translation.z());
  const double height = multibody::center_of_mass(model, data).z() - ground;
  if (!(height > 0))
    throw std::invalid_argument("BalanceController: the reference's CoM is not above its soles");
  return std::sqrt(-model.gravity.z() / height);
}

/// @p sensors read once per control period @p dt (s).
multibody::sensors::RobotSensorParameters
at_period(multibody::sensors::RobotSensorParameters sensors, double dt) {
  sensors.period = dt;
  return sensors;
}

} // namespace

BalanceController::BalanceController(const multibody::Model& model, const Humanoid& humanoid,
                                     const BalanceParameters& parameters, double dt, bool stabilize)
    : model_(model), humanoid_(humanoid), parameters_(parameters), dt_(dt), stabilize_(stabilize),
      sensors_(model, at_period(parameters.sensors, dt)),
      estimator_(model, humanoid, parameters.sensors.imu_frame, parameters.estimator, dt),
      stabilizer_(parameters.stabilizer), touchdown_(parameters.touchdown), step_(parameters.step),
      timing_(parameters.timing), reference_data_(model), true_data_(model), leg_data_(model),
      jacobian_(6, model.nv) {
  if (!(parameters.zmp_time_constant > 0 && parameters.contact_height > 0))
    throw std::invalid_argument("BalanceController: ZMP time constant and contact height > 0");
  for (int foot = 0; foot < 2; ++foot) {
    const multibody::Frame& sole = model.frames[humanoid.sole_frames[foot]];
    const multibody::Frame& sensor = model.frames[parameters.sensors.force_frames[foot]];
    if (sole.body != sensor.body)
      throw std::invalid_argument(
          "BalanceController: the " + std::string(to_string(leg_sides[foot])) +
          " force sensor frame '" + sensor.name + "' is not on the foot's body");
    sensor_in_sole_[foot] = sole.placement.inverse() * sensor.placement;
  }
}

void BalanceController::update(const Eigen::Ref<const Eigen::VectorXd>& q,
                               const Eigen::Ref<const Eigen::VectorXd>& v,
                               const Eigen::Ref<const Eigen::VectorXd>& a,
                               const std::array<multibody::Vector6d, 2>& ground_wrenches,
                               Eigen::Ref<Eigen::VectorXd> q_ref) {
  // Reference: CoM, DCM, ZMP, soles.
  if (first_) {
    omega_ = reference_omega(model_, humanoid_, reference_data_, q_ref);
    DcmStabilizerParameters p = parameters_.stabilizer;
    p.omega = omega_;
    stabilizer_ = DcmStabilizer(p);
  }
  multibody::forward_kinematics(model_, reference_data_, q_ref);
  // Over real time: a faster reference (step timing) has a faster DCM.
  const Eigen::Vector3d com_ref = multibody::center_of_mass(model_, reference_data_);
  const Eigen::Vector3d com_ref_velocity =
      first_ ? Eigen::Vector3d::Zero() : Eigen::Vector3d((com_ref - com_ref_) / dt_);
  const Eigen::Vector2d dcm_ref = (com_ref + com_ref_velocity / omega_).head<2>();
  const Eigen::Vector2d zmp_now =
      first_ ? dcm_ref : Eigen::Vector2d(dcm_ref - (dcm_ref - dcm_ref_) / (dt_ * omega_));
  if (first_)
    zmp_ref_ = zmp_now;
  else
    zmp_ref_ += dt_ / (parameters_.zmp_time_constant + dt_) * (zmp_now - zmp_ref_);
  com_ref_ = com_ref;
  dcm_ref_ = dcm_ref;
  dcm_target_ = dcm_ref + step_.dcm_shift();
  zmp_target_ = zmp_ref_ + step_.zmp_shift();
  std::array<Eigen::Vector3d, 2> soles;
  for (int foot = 0; foot < 2; ++foot) {
    const multibody::SE3 sole =
        multibody::frame_placement(model_, reference_data_, humanoid_.sole_frames[foot]);
    soles[foot] = sole.translation;
    reference_soles_[foot] = sole.translation;
    soles[foot].head<2>() += step_.anchor_shift(foot);
    feet_[foot].position = soles[foot];
    feet_[foot].rotation = sole.rotation;
    if (first_) {
      ground_height_[foot] = sole.translation.z();
      planned_ground0_[foot] = planned_ground_[foot];
    }
  }

  // Sensors.
  multibody::forward_kinematics(model_, true_data_, q, v, a);
  const multibody::sensors::SensorReadings& readings =
      sensors_.measure(true_data_, q, ground_wrenches);
  std::array<double, 2> normal{};
  std::array<multibody::Vector6d, 2> sole_wrenches;
  Eigen::Vector2d clearance, normal_force;
  for (int foot = 0; foot < 2; ++foot) {
    const multibody::Vector6d& at_sole = sole_wrenches[foot] =
        sensor_in_sole_[foot].act_force(readings.foot_wrenches[foot]);
    feet_[foot].force = at_sole.head<3>();
    feet_[foot].moment = at_sole.tail<3>();
    normal[foot] = normal_force[foot] = at_sole[2];
    const double ground = ground_height_[foot] + planned_ground_[foot] - planned_ground0_[foot];
    clearance[foot] = soles[foot].z() - ground;
  }
  const Eigen::Vector2d& dz = touchdown_.update(clearance, normal_force, dt_);
  for (int foot = 0; foot < 2; ++foot) {
    feet_[foot].contact =
        clearance[foot] + dz[foot] - touchdown_.levels()[foot] < parameters_.contact_height &&
        normal[foot] > parameters_.stabilizer.min_contact_force;
    soles[foot].z() += dz[foot];
    feet_[foot].position.z() += dz[foot];
  }

  // Estimate (and the truth, for the statistics).
  const Eigen::Vector3d com_true = multibody::center_of_mass(model_, true_data_);
  const Eigen::Vector3d com_true_velocity =
      multibody::center_of_mass_jacobian(model_, true_data_) * v;
  if (parameters_.estimate == StateEstimate::ground_truth)
    estimator_.set(com_true, com_true_velocity);
  else {
    estimator_.set_unsensed(q_ref); // e.g. ankle springs at the plan's deflection
    estimator_.update(readings.encoders, readings.imu.orientation, soles, sole_wrenches);
  }
  const Eigen::Vector2d dcm = estimator_.dcm(omega_).head<2>();
  const Eigen::Vector2d dcm_true = (com_true + com_true_velocity / omega_).head<2>();
  statistics_.dcm_error = dcm - dcm_target_;
  statistics_.true_dcm_error = dcm_true - dcm_target_;
  statistics_.max_true_dcm_error =
      std::max(statistics_.max_true_dcm_error, statistics_.true_dcm_error.norm());
  statistics_.max_dcm_error = std::max(statistics_.max_dcm_error, statistics_.dcm_error.norm());
  statistics_.max_com_estimate_error =
      std::max(statistics_.max_com_estimate_error, (estimator_.com() - com_true).norm());
  statistics_.max_dcm_estimate_error =
      std::max(statistics_.max_dcm_estimate_error, (dcm - dcm_true).norm());
  first_ = false;
  if (!stabilize_)
    return;

  // Stabilizer and joint references.
  stabilizer_.update(dcm, dcm_target_, zmp_target_, feet_, dt_);
  std::array<Eigen::Matrix2d, 2> yaw;
  std::array<bool, 2> touched;
  for (int foot = 0; foot < 2; ++foot) {
    const Eigen::Matrix3d& r = feet_[foot].rotation;
    const double angle = std::atan2(r(1, 0), r(0, 0));
    yaw[foot] << std::cos(angle), -std::sin(angle), std::sin(angle), std::cos(angle);
    touched[foot] = normal[foot] > parameters_.touchdown.force;
  }
  // The step's deficit: the DCM error about the stance sole's centre (for the reference ZMP,
  // whose filtered value lags the transfer at lift-off) beyond the sole's rectangle. Not its
  // planned support polygon: that is the ground the unloaded sole touches, and a landing moved
  // for it leaves the foothold the plan chose (docs/stabilizer.md).
  Eigen::Vector2d deficit = Eigen::Vector2d::Zero();
  const bool right_swings = swings_[0].progress >= 0, left_swings = swings_[1].progress >= 0;
  if (right_swings != left_swings) {
    StabilizerFoot stance = feet_[right_swings ? 1 : 0];
    stance.support = nullptr;
    if (stance.contact)
      deficit = stabilizer_.cop_excess(stance, stance.position.head<2>() + statistics_.dcm_error,
                                       parameters_.step.cop_margin);
  }
  std::array<Eigen::Vector2d, 2> sensed;
  for (int foot = 0; foot < 2; ++foot) {
    const Eigen::Vector3d sole =
        parameters_.estimate == StateEstimate::ground_truth
            ? multibody::frame_placement(model_, true_data_, humanoid_.sole_frames[foot])
                  .translation
            : estimator_.soles()[foot];
    sensed[foot] = (sole - reference_soles_[foot]).head<2>();
  }
  step_.update(swing_time_, swings_, yaw, touched, sensed, deficit, omega_, 1.0, dt_);
  timing_.update(swing_time_, swings_, touched, statistics_.dcm_error, deficit,
                 omega_ * (dcm_target_ - zmp_target_), dt_);
  for (int foot = 0; foot < 2; ++foot) {
    const FootOffset& o = stabilizer_.offsets()[foot];
    multibody::frame_jacobian(model_, reference_data_, humanoid_.sole_frames[foot], jacobian_);
    for (int j = 0; j < 6; ++j)
      leg_jacobian_.col(j) = jacobian_.col(model_.idx_v[humanoid_.leg_joints[foot][j]]);
    multibody::Vector6d motion;
    const Eigen::Vector2d shift = step_.foot_shift(foot) - step_.com_shift();
    motion.head<3>() << shift.x(), shift.y(), o.height + dz[foot];
    motion.tail<3>() = feet_[foot].rotation * Eigen::Vector3d(o.roll, o.pitch, 0);
    leg_lu_.compute(leg_jacobian_);
    const multibody::Vector6d dq = leg_lu_.solve(motion);
    for (int j = 0; j < 6; ++j)
      q_ref[model_.idx_q[humanoid_.leg_joints[foot][j]]] += dq[j];
    const multibody::SE3 sole =
        multibody::frame_placement(model_, reference_data_, humanoid_.sole_frames[foot]);
    sole_targets_[foot] = multibody::SE3(
        multibody::exp3_quaternion(motion.tail<3>()).toRotationMatrix() * sole.rotation,
        sole.translation + motion.head<3>());
  }
  if ((step_.foot_shift(0) - step_.com_shift()).squaredNorm() +
          (step_.foot_shift(1) - step_.com_shift()).squaredNorm() ==
      0)
    return; // no shift (step adjustment off or idle): the linear offsets are the stabilizer's
  // The step's shifts reach a decimetre: Newton on each leg to the offset sole pose.
  for (int iteration = 0; iteration < parameters_.step.leg_iterations; ++iteration) {
    multibody::forward_kinematics(model_, leg_data_, q_ref);
    for (int foot = 0; foot < 2; ++foot) {
      const multibody::SE3 sole =
          multibody::frame_placement(model_, leg_data_, humanoid_.sole_frames[foot]);
      multibody::Vector6d error;
      error.head<3>() = sole_targets_[foot].translation - sole.translation;
      error.tail<3>() = multibody::log3(sole_targets_[foot].rotation * sole.rotation.transpose());
      multibody::frame_jacobian(model_, leg_data_, humanoid_.sole_frames[foot], jacobian_);
      for (int j = 0; j < 6; ++j)
        leg_jacobian_.col(j) = jacobian_.col(model_.idx_v[humanoid_.leg_joints[foot][j]]);
      leg_lu_.compute(leg_jacobian_);
      const multibody::Vector6d dq = leg_lu_.solve(error);
      for (int j = 0; j < 6; ++j)
        q_ref[model_.idx_q[humanoid_.leg_joints[foot][j]]] += dq[j];
    }
  }
}

} // namespace plantar::walking
