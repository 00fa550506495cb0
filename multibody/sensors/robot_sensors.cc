#include "multibody/sensors/robot_sensors.h"

#include "multibody/kinematics.h"
#include "multibody/sensors/force_torque_sensor.h"

#include <Eigen/Geometry>

#include <cmath>
#include <stdexcept>
#include <string>

namespace plantar::multibody::sensors {
namespace {

// Layout of the packed signal vector.
constexpr int rotation_at = 0, orientation_noise_at = 9, gyro_at = 12, accel_at = 15,
              encoders_at = 18;

void check_frame(const Model& model, int frame, const char* what) {
  if (frame < 0 || frame >= static_cast<int>(model.frames.size()))
    throw std::invalid_argument(std::string("RobotSensors: ") + what + " frame " +
                                std::to_string(frame) + " is not a frame of the model");
}

} // namespace

RobotSensors::RobotSensors(const Model& model, const RobotSensorParameters& parameters)
    : model_(model), parameters_(parameters) {
  check_frame(model, parameters.imu_frame, "IMU");
  check_frame(model, parameters.force_frames[0], "right force sensor");
  check_frame(model, parameters.force_frames[1], "left force sensor");
  for (int iq : parameters.encoder_q)
    if (iq < 0 || iq >= model.nq)
      throw std::invalid_argument("RobotSensors: encoder index " + std::to_string(iq) +
                                  " outside the configuration");
  if (!(parameters.force_bandwidth >= 0) ||
      (parameters.force_bandwidth > 0 && !(parameters.period > 0)))
    throw std::invalid_argument("RobotSensors: force bandwidth " +
                                std::to_string(parameters.force_bandwidth) + " Hz with period " +
                                std::to_string(parameters.period) +
                                " s: want a bandwidth >= 0 and, when > 0, a period > 0");
  if (parameters.force_bandwidth > 0)
    force_alpha_ = -std::expm1(-2 * M_PI * parameters.force_bandwidth * parameters.period);
  const int n_enc = static_cast<int>(parameters.encoder_q.size());
  const int n = encoders_at + n_enc + 12;
  Eigen::VectorXd noise = Eigen::VectorXd::Zero(n), bias = Eigen::VectorXd::Zero(n);
  auto set = [&](int at, int count, const NoiseModel& m) {
    noise.segment(at, count).setConstant(m.noise);
    bias.segment(at, count).setConstant(m.bias);
  };
  set(orientation_noise_at, 3, parameters.orientation);
  set(gyro_at, 3, parameters.angular_velocity);
  set(accel_at, 3, parameters.linear_acceleration);
  set(encoders_at, n_enc, parameters.encoder);
  for (int foot = 0; foot < 2; ++foot) {
    set(encoders_at + n_enc + 6 * foot, 3, parameters.force);
    set(encoders_at + n_enc + 6 * foot + 3, 3, parameters.torque);
  }
  channel_ = SensorChannel(noise, bias, parameters.delay, parameters.seed);
  packed_.setZero(n);
  readings_.encoders.setZero(n_enc);
}

const SensorReadings& RobotSensors::measure(const Data& data,
                                            const Eigen::Ref<const Eigen::VectorXd>& q,
                                            const std::array<Vector6d, 2>& ground_wrenches) {
  const ImuReading imu = read_imu(model_, data, parameters_.imu_frame);
  packed_.segment<9>(rotation_at) =
      Eigen::Map<const Eigen::Matrix<double, 9, 1>>(imu.orientation.data());
  packed_.segment<3>(orientation_noise_at).setZero();
  packed_.segment<3>(gyro_at) = imu.angular_velocity;
  packed_.segment<3>(accel_at) = imu.linear_acceleration;
  const int n_enc = static_cast<int>(parameters_.encoder_q.size());
  for (int j = 0; j < n_enc; ++j)
    packed_[encoders_at + j] = q[parameters_.encoder_q[j]];
  for (int foot = 0; foot < 2; ++foot) {
    const SE3 sensor = frame_placement(model_, data, parameters_.force_frames[foot]);
    packed_.segment<6>(encoders_at + n_enc + 6 * foot) =
        wrench_at_sensor(sensor, ground_wrenches[foot]);
  }

  const Eigen::VectorXd& y = channel_.measure(packed_);
  const Eigen::Matrix3d rotation =
      Eigen::Map<const Eigen::Matrix3d>(y.segment<9>(rotation_at).data());
  const Eigen::Vector3d e = y.segment<3>(orientation_noise_at);
  const double angle = e.norm();
  readings_.imu.orientation =
      angle > 0 ? Eigen::Matrix3d(rotation * Eigen::AngleAxisd(angle, e / angle).toRotationMatrix())
                : rotation;
  readings_.imu.angular_velocity = y.segment<3>(gyro_at);
  readings_.imu.linear_acceleration = y.segment<3>(accel_at);
  readings_.encoders = y.segment(encoders_at, n_enc);
  for (int foot = 0; foot < 2; ++foot) {
    const auto sample = y.segment<6>(encoders_at + n_enc + 6 * foot);
    Vector6d& filtered = readings_.foot_wrenches[foot];
    filtered = first_ || force_alpha_ == 1
                   ? Vector6d(sample)
                   : Vector6d(filtered + force_alpha_ * (sample - filtered));
  }
  first_ = false;
  return readings_;
}

} // namespace plantar::multibody::sensors
