// The simulated sensors (multibody/sensors/): the F/T wrench against a hand computation, the
// IMU's acceleration and angular velocity against finite differences of the frame's motion,
// standing still the two F/T sensors carrying m g, and the noise, bias and delay of a channel
// against their definitions (sample mean and standard deviation, a shift by k samples), and the
// F/T low-pass against the closed forms of a first-order recurrence (step, sine, alternation).
#include "multibody/configuration.h"
#include "multibody/data.h"
#include "multibody/jacobian.h"
#include "multibody/kinematics.h"
#include "multibody/sensors/force_torque_sensor.h"
#include "multibody/sensors/imu.h"
#include "multibody/sensors/robot_sensors.h"
#include "multibody/sensors/sensor_channel.h"
#include "multibody/stepper.h"
#include "multibody/urdf_loader.h"
#include "tests/multibody/test_helpers.h"

#include <gtest/gtest.h>

#include <cmath>
#include <complex>
#include <cstdio>
#include <vector>

namespace plantar::multibody::sensors {
namespace {

using test::model_path;

TEST(ForceTorqueSensor, WrenchAgainstHandComputation) {
  // Two contact forces; the sensor 0.1 m above the origin, turned 90 degrees about z
  // (x_s = world y, y_s = world -x).
  Eigen::Matrix3Xd points(3, 2), forces(3, 2);
  points << 0.1, -0.1, 0.0, 0.05, 0.0, 0.0;
  forces << 0.0, 10.0, 0.0, 0.0, 100.0, 200.0;
  SE3 sensor;
  sensor.rotation << 0, -1, 0, 1, 0, 0, 0, 0, 1;
  sensor.translation << 0, 0, 0.1;
  const Vector6d wrench = wrench_at_sensor(sensor, contact_wrench(points, forces));
  // By hand: f = (10, 0, 300); about o: r1 x f1 = (0.1, 0, -0.1) x (0, 0, 100) = (0, -10, 0),
  // r2 x f2 = (-0.1, 0.05, -0.1) x (10, 0, 200) = (10, 19, -0.5); n = (10, 9, -0.5).
  // Sensor axes (v_y, -v_x, v_z): f_s = (0, -10, 300), n_s = (9, -10, -0.5).
  Vector6d expected;
  expected << 0, -10, 300, 9, -10, -0.5;
  std::printf("F/T wrench (%g %g %g | %g %g %g), hand (0 -10 300 | 9 -10 -0.5)\n", wrench[0],
              wrench[1], wrench[2], wrench[3], wrench[4], wrench[5]);
  EXPECT_LT((wrench - expected).cwiseAbs().maxCoeff(), 1e-12);
}

TEST(Imu, AccelerationAndAngularVelocityAgainstFiniteDifferences) {
  // HRP-2 with a constant base twist (q_base(t) = q0 exp(t V), exact) and sinusoidal joints;
  // the IMU on a frame of the chest, offset from its body origin.
  Model model = build_model_from_urdf(model_path("hrp2/hrp2.urdf"));
  const int chest = model.body_id("CHEST_LINK1");
  Frame imu_frame;
  imu_frame.name = "test_imu";
  imu_frame.body = chest;
  imu_frame.placement.rotation =
      Eigen::AngleAxisd(0.3, Eigen::Vector3d(1, 2, 3).normalized()).toRotationMatrix();
  imu_frame.placement.translation << 0.05, -0.03, 0.12;
  model.frames.push_back(imu_frame);
  const int frame = static_cast<int>(model.frames.size()) - 1;
  Data data(model);

  std::mt19937 rng(3);
  const Eigen::VectorXd q0 = test::random_configuration(model, rng);
  Eigen::VectorXd twist = Eigen::VectorXd::Zero(model.nv);
  twist.head<6>() << 0.3, -0.2, 0.1, 0.7, -0.4, 0.5;
  const Eigen::VectorXd amplitude = 0.3 * test::random_vector(model.nv, rng);
  const Eigen::VectorXd rate = 2.0 + 3.0 * test::random_vector(model.nv, rng).array().abs();
  // State at t: base from q0 by exp(t V); joint j = q0_j + A_j sin(w_j t).
  auto state = [&](double t, Eigen::VectorXd& q, Eigen::VectorXd& v, Eigen::VectorXd& a) {
    integrate(model, q0, twist, t, q);
    v = twist;
    a = Eigen::VectorXd::Zero(model.nv);
    for (int i = 2; i < model.n_bodies; ++i) {
      const int iq = model.idx_q[i], iv = model.idx_v[i];
      q[iq] = q0[iq] + amplitude[iv] * std::sin(rate[iv] * t);
      v[iv] = amplitude[iv] * rate[iv] * std::cos(rate[iv] * t);
      a[iv] = -amplitude[iv] * rate[iv] * rate[iv] * std::sin(rate[iv] * t);
    }
  };
  Eigen::VectorXd q = q0, v, a;
  auto point_velocity = [&](double t) -> Eigen::Vector3d {
    state(t, q, v, a);
    forward_kinematics(model, data, q, v);
    Eigen::MatrixXd jacobian(3, model.nv);
    point_jacobian(model, data, chest, imu_frame.placement.translation, jacobian);
    return jacobian * v;
  };
  auto orientation = [&](double t) -> Eigen::Matrix3d {
    state(t, q, v, a);
    forward_kinematics(model, data, q);
    return frame_placement(model, data, frame).rotation;
  };
  double worst_acceleration = 0, worst_rate = 0;
  const double h = 1e-5;
  for (const double t : {0.0, 0.37, 1.1}) {
    state(t, q, v, a);
    forward_kinematics(model, data, q, v, a);
    const ImuReading imu = read_imu(model, data, frame);
    // World acceleration by central difference of the point's velocity; the IMU's is
    // R_s f_s + g.
    const Eigen::Vector3d fd = (point_velocity(t + h) - point_velocity(t - h)) / (2 * h);
    const Eigen::Vector3d measured = imu.orientation * imu.linear_acceleration + model.gravity;
    worst_acceleration = std::max(worst_acceleration, (fd - measured).norm() / fd.norm());
    // Angular velocity in sensor axes: R^T dR/dt = [w]x.
    const Eigen::Matrix3d dr = (orientation(t + h) - orientation(t - h)) / (2 * h);
    const Eigen::Matrix3d w = imu.orientation.transpose() * dr;
    const Eigen::Vector3d w_fd(w(2, 1), w(0, 2), w(1, 0));
    worst_rate =
        std::max(worst_rate, (w_fd - imu.angular_velocity).norm() / imu.angular_velocity.norm());
    std::printf("t = %.2f s: a_fd = (%.5f %.5f %.5f), IMU R f + g = (%.5f %.5f %.5f) m/s^2\n", t,
                fd.x(), fd.y(), fd.z(), measured.x(), measured.y(), measured.z());
  }
  std::printf("IMU against central differences (h = 1e-5 s): worst relative error %.2e "
              "(acceleration), %.2e (angular velocity); tolerance 1e-6\n",
              worst_acceleration, worst_rate);
  EXPECT_LT(worst_acceleration, 1e-6);
  EXPECT_LT(worst_rate, 1e-6);

  // At rest the accelerometer reads -g in its own axes (+9.81 up).
  q = q0;
  v.setZero();
  a.setZero();
  forward_kinematics(model, data, q, v, a);
  const ImuReading rest = read_imu(model, data, frame);
  EXPECT_LT((rest.orientation * rest.linear_acceleration - Eigen::Vector3d(0, 0, 9.81)).norm(),
            1e-12);
}

TEST(RobotSensors, StandingStillTheForceSensorsCarryTheWeight) {
  // HRP-2 on four corners per sole under stiff PD for 1 s (as multibody_stepper_test); the F/T
  // sensors at the ankle links read the contact forces of their foot's points.
  const Model model = build_model_from_urdf(model_path("hrp2/hrp2.urdf"));
  StepperParameters parameters;
  parameters.time_step = 1e-3;
  Stepper stepper(model, parameters);
  stepper.set_gains(PdGains::Uniform(model, 1e4, 200.0));
  std::array<std::vector<int>, 2> foot_points;
  std::array<std::vector<Eigen::Vector3d>, 2> foot_local;
  std::array<int, 2> foot_body{};
  const char* soles[2] = {"r_sole", "l_sole"};
  for (int foot = 0; foot < 2; ++foot) {
    const Frame& frame = model.frames[model.frame_id(soles[foot])];
    foot_body[foot] = frame.body;
    for (const double x : {-0.1086, 0.1086})
      for (const double y : {-0.069, 0.069}) {
        const Eigen::Vector3d p = frame.placement.act_point(Eigen::Vector3d(x, y, 0));
        foot_points[foot].push_back(stepper.add_contact_point(frame.body, p, 0.8));
        foot_local[foot].push_back(p);
      }
  }
  Data data(model);
  Eigen::VectorXd q = model.neutral_configuration();
  forward_kinematics(model, data, q);
  q[2] = -frame_placement(model, data, model.frame_id("r_sole")).translation.z();
  const Eigen::VectorXd q_ref = q, zero = Eigen::VectorXd::Zero(model.nv);
  Eigen::VectorXd v = zero;
  for (int n = 0; n < 1000; ++n)
    stepper.step(q, v, zero, q_ref, zero);

  RobotSensorParameters sensor_parameters;
  sensor_parameters.imu_frame = model.frame_id("BODY");
  sensor_parameters.force_frames = {model.frame_id("RLEG_LINK5"), model.frame_id("LLEG_LINK5")};
  RobotSensors sensors(model, sensor_parameters);
  forward_kinematics(model, data, q, v, zero);
  std::array<Vector6d, 2> ground;
  for (int foot = 0; foot < 2; ++foot) {
    Eigen::Matrix3Xd points(3, 4), forces(3, 4);
    for (int k = 0; k < 4; ++k) {
      points.col(k) = data.oMi[foot_body[foot]].act_point(foot_local[foot][k]);
      const Eigen::Vector3d& p = stepper.point_impulse(foot_points[foot][k]); // (n, t1, t2)
      forces.col(k) = Eigen::Vector3d(p[1], p[2], p[0]) / parameters.time_step;
    }
    ground[foot] = contact_wrench(points, forces);
  }
  const SensorReadings& readings = sensors.measure(data, q, ground);
  Eigen::Vector3d total = Eigen::Vector3d::Zero();
  for (int foot = 0; foot < 2; ++foot) {
    const SE3 sensor = frame_placement(model, data, sensor_parameters.force_frames[foot]);
    total += sensor.rotation * readings.foot_wrenches[foot].head<3>();
  }
  const double weight = model.total_mass() * 9.81;
  std::printf("standing 1 s: F/T sensors sum (%.4f, %.4f, %.4f) N, m g = %.4f N\n", total.x(),
              total.y(), total.z(), weight);
  EXPECT_NEAR(total.z() / weight, 1.0, 1e-3);
  EXPECT_LT(std::abs(total.x()) + std::abs(total.y()), 1e-3 * weight);
  // Standing still: the accelerometer reads g up in the world.
  EXPECT_NEAR((readings.imu.orientation * readings.imu.linear_acceleration).z(), 9.81, 1e-2);
}

TEST(RobotSensors, ForceBandwidthIsAFirstOrderLowPass) {
  // HRP-2 at rest; ground wrenches as inputs. With f_c > 0 each F/T signal y_f follows
  // y_f,n = y_f,n-1 + alpha (y_n - y_f,n-1), alpha = 1 - exp(-2 pi f_c dt), from y_f,0 = y_0,
  // y_n the unfiltered reading (f_c = 0, the same sensors otherwise).
  const Model model = build_model_from_urdf(model_path("hrp2/hrp2.urdf"));
  Data data(model);
  const Eigen::VectorXd q = model.neutral_configuration(), zero = Eigen::VectorXd::Zero(model.nv);
  forward_kinematics(model, data, q, zero, zero);
  RobotSensorParameters raw_parameters;
  raw_parameters.imu_frame = model.frame_id("BODY");
  raw_parameters.force_frames = {model.frame_id("RLEG_LINK5"), model.frame_id("LLEG_LINK5")};
  RobotSensorParameters filtered_parameters = raw_parameters;
  const double f_c = 25, dt = 5e-4, alpha = 1 - std::exp(-2 * M_PI * f_c * dt);
  filtered_parameters.force_bandwidth = f_c;
  filtered_parameters.period = dt;

  Vector6d w0, w1;
  w0 << 1, -2, 300, 0.5, -1, 0.1;
  w1 << -3, 4, 150, -2, 3, -0.4;
  auto ground = [](const Vector6d& w) { return std::array<Vector6d, 2>{w, -0.5 * w}; };
  // A step from w0 to w1 at n = 1: y_f,n - y_1 = (y_0 - y_1) (1 - alpha)^n.
  {
    RobotSensors raw(model, raw_parameters), filtered(model, filtered_parameters);
    const std::array<Vector6d, 2> y0 = raw.measure(data, q, ground(w0)).foot_wrenches;
    const std::array<Vector6d, 2> y1 = raw.measure(data, q, ground(w1)).foot_wrenches;
    double worst = 0;
    for (int n = 0; n < 200; ++n) {
      const SensorReadings& r = filtered.measure(data, q, ground(n == 0 ? w0 : w1));
      for (int foot = 0; foot < 2; ++foot) {
        const Vector6d expected = y1[foot] + (y0[foot] - y1[foot]) * std::pow(1 - alpha, n);
        worst = std::max(worst, (r.foot_wrenches[foot] - expected).cwiseAbs().maxCoeff());
      }
    }
    std::printf("F/T low-pass (25 Hz, dt 0.5 ms, alpha %.6f): step response against "
                "(1 - alpha)^n, worst %.2e N (N m)\n",
                alpha, worst);
    EXPECT_LT(worst, 1e-10);
  }
  // Steady sine of frequency f: gain |alpha / (1 - (1 - alpha) exp(-i w dt))| (about 1/sqrt(2)
  // at f_c); at the Nyquist frequency (alternating sign) alpha / (2 - alpha).
  for (const double f : {f_c, 1 / (2 * dt)}) {
    RobotSensors filtered(model, filtered_parameters);
    const double w = 2 * M_PI * f;
    const std::complex<double> z = std::polar(1.0, -w * dt);
    const double gain = std::abs(alpha / (1.0 - (1 - alpha) * z));
    double peak = 0;
    for (int n = 0; n < 4000; ++n) {
      const double s = std::cos(w * n * dt);
      const SensorReadings& r = filtered.measure(data, q, ground(w0 * s));
      if (n >= 3000) // the start's transient has decayed by (1 - alpha)^3000
        peak = std::max(peak, std::abs(r.foot_wrenches[0][2]));
    }
    RobotSensors raw(model, raw_parameters);
    const double amplitude = std::abs(raw.measure(data, q, ground(w0)).foot_wrenches[0][2]);
    std::printf("  sine at %g Hz: gain %.5f, closed form %.5f\n", f, peak / amplitude, gain);
    // The sampled peak of a sine (up to cos(w dt / 2) below the amplitude at 25 Hz).
    EXPECT_NEAR(peak / amplitude, gain, 0.004 * gain);
  }
  RobotSensorParameters bad = filtered_parameters;
  bad.force_bandwidth = -1;
  EXPECT_THROW(RobotSensors(model, bad), std::invalid_argument);
  bad.force_bandwidth = 25;
  bad.period = 0;
  EXPECT_THROW(RobotSensors(model, bad), std::invalid_argument);
}

TEST(SensorChannel, DelayBiasAndNoiseAsDefined) {
  const int k = 3;
  SensorChannel delayed(Eigen::VectorXd::Zero(2), Eigen::Vector2d(0.5, -1.0), k, 1);
  for (int n = 0; n < 10; ++n) {
    const Eigen::Vector2d truth(n, 10.0 * n);
    const Eigen::VectorXd& y = delayed.measure(truth);
    const double expected = std::max(n - k, 0);
    EXPECT_DOUBLE_EQ(y[0], expected + 0.5) << "sample " << n;
    EXPECT_DOUBLE_EQ(y[1], 10.0 * expected - 1.0) << "sample " << n;
  }
  // Noise: sample mean -> bias, standard deviation -> sigma (N = 1e5: the mean's standard
  // error is sigma / 316).
  const double sigma = 0.2, bias = 0.05;
  SensorChannel noisy(Eigen::VectorXd::Constant(1, sigma), Eigen::VectorXd::Constant(1, bias), 0,
                      7);
  SensorChannel same_seed(Eigen::VectorXd::Constant(1, sigma), Eigen::VectorXd::Constant(1, bias),
                          0, 7);
  const int n = 100000;
  double sum = 0, sum2 = 0;
  for (int i = 0; i < n; ++i) {
    const double y = noisy.measure(Eigen::VectorXd::Constant(1, 1.0))[0] - 1.0;
    EXPECT_EQ(y, same_seed.measure(Eigen::VectorXd::Constant(1, 1.0))[0] - 1.0);
    sum += y;
    sum2 += y * y;
  }
  const double mean = sum / n, std_dev = std::sqrt(sum2 / n - mean * mean);
  std::printf("noise: mean %.5f (bias %.2f), std %.5f (sigma %.2f)\n", mean, bias, std_dev, sigma);
  EXPECT_NEAR(mean, bias, 4 * sigma / std::sqrt(n));
  EXPECT_NEAR(std_dev, sigma, 0.01 * sigma);
  EXPECT_THROW(SensorChannel(Eigen::VectorXd::Zero(1), Eigen::VectorXd::Zero(1), -1, 1),
               std::invalid_argument);
}

} // namespace
} // namespace plantar::multibody::sensors
