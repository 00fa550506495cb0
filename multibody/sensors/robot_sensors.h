#pragma once
// The sensors of a humanoid as a real one has them: an IMU on one frame (the waist), joint
// encoders on the controlled joints and a 6-axis force/torque sensor on each foot, read from
// the simulated state with optional white noise, bias and a common delay of k control periods
// (sensor_channel.h). The frames and joints come from the scene, never from code.
//
// Per call of measure(), from the state (q, v), the generalized acceleration a (nv) and the
// ground wrench on each foot:
//   IMU (imu.h): R_s exp([e]x) with e the orientation noise (rad), w_s, f_s
//   encoders: the controlled joints' q
//   F/T (force_torque_sensor.h): [f_s; n_s] of each foot at its sensor frame, optionally
//     through a first-order low-pass of cut-off f_c (the sensor's and its amplifier's
//     bandwidth), after the channel's delay, bias and noise:
//       y_f,n = y_f,n-1 + alpha (y_n - y_f,n-1),  alpha = 1 - exp(-2 pi f_c dt),  y_f,0 = y_0
// Constant once built; measure() allocates nothing.

#include "multibody/data.h"
#include "multibody/model.h"
#include "multibody/sensors/imu.h"
#include "multibody/sensors/sensor_channel.h"
#include "multibody/spatial.h"

#include <Eigen/Core>

#include <array>
#include <cstdint>
#include <vector>

namespace plantar::multibody::sensors {

/// White-noise standard deviation and bias of one kind of signal (same on each axis).
struct NoiseModel {
  double noise = 0; ///< sigma, >= 0, the signal's unit
  double bias = 0;  ///< constant offset, the signal's unit
};

struct RobotSensorParameters {
  int imu_frame = -1;                ///< model frame of the IMU
  std::array<int, 2> force_frames{}; ///< model frames of the right and left F/T sensors
  std::vector<int> encoder_q;        ///< configuration indices of the encoded joints
  NoiseModel orientation;            ///< rad (a rotation vector applied in the sensor frame)
  NoiseModel angular_velocity;       ///< rad/s
  NoiseModel linear_acceleration;    ///< m/s^2
  NoiseModel encoder;                ///< rad (m for prismatic joints)
  NoiseModel force;                  ///< N
  NoiseModel torque;                 ///< N m
  int delay = 0;                     ///< k control periods, >= 0
  double force_bandwidth = 0;        ///< f_c of the F/T low-pass, Hz, >= 0; 0: none
  double period = 0;                 ///< dt between calls of measure(), s (> 0 with f_c > 0)
  std::uint32_t seed = 1;            ///< of the noise generator
};

struct SensorReadings {
  ImuReading imu;
  Eigen::VectorXd encoders;                ///< per encoded joint
  std::array<Vector6d, 2> foot_wrenches{}; ///< right, left: [f_s; n_s] at the sensor frame
};

class RobotSensors {
public:
  /// Throws std::invalid_argument for a frame or index outside @p model, a negative delay or
  /// bandwidth, or a bandwidth without a positive period.
  RobotSensors(const Model& model, const RobotSensorParameters& parameters);
  const RobotSensorParameters& parameters() const { return parameters_; }
  /// Measures. Requires forward_kinematics(model, data, q, v, a) on @p data.
  /// @param q configuration (nq); @param ground_wrenches the ground's wrench on the right and
  /// left foot, [f; n] about the world origin, world axes (N, N m). Valid until the next call.
  const SensorReadings& measure(const Data& data, const Eigen::Ref<const Eigen::VectorXd>& q,
                                const std::array<Vector6d, 2>& ground_wrenches);

private:
  const Model& model_;
  RobotSensorParameters parameters_;
  SensorChannel channel_;  ///< all signals packed: see measure()
  Eigen::VectorXd packed_; ///< 9 + 3 + 3 + 3 + n_enc + 12
  SensorReadings readings_;
  double force_alpha_ = 1; ///< the F/T low-pass's alpha (1: none)
  bool first_ = true;
};

} // namespace plantar::multibody::sensors
