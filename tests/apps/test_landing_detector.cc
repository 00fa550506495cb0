// The landing detector (issue 23) on synthetic vertical forces against closed forms: a ramp,
// a half-sine pulse (impulse 2 F T / pi, rise time T / pi (asin 0.9 - asin 0.1)); arming,
// bounces inside the window, a run ending in a window; landings.csv.
#include "apps/landing_detector.h"

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <functional>
#include <gtest/gtest.h>
#include <sstream>
#include <string>
#include <vector>

using namespace plantar::app;

namespace {

/// Feeds @p force(t) and @p acceleration(t) at t_n = n dt, n = 0 .. n_samples - 1.
std::vector<Landing> detect(const LandingParameters& params, double dt, int n_samples,
                            const std::function<double(double)>& force,
                            const std::function<double(double)>& acceleration) {
  LandingDetector detector(params, dt, n_samples);
  for (int n = 0; n < n_samples; ++n)
    detector.update(n * dt, force(n * dt), acceleration(n * dt));
  detector.finish();
  return detector.landings();
}

/// P sin(pi (t - t0) / T) on [t0, t0 + T], 0 elsewhere.
double half_sine(double t, double peak, double start, double duration) {
  return t >= start && t <= start + duration ? peak * std::sin(M_PI * (t - start) / duration) : 0.0;
}

} // namespace

TEST(LandingDetector, RampAgainstClosedForms) {
  // F = k (t - t0) after t0: touchdown t0 + F_th / k (exact: linear between samples);
  // window samples t_n in (t_td, t_td + W]: peak k (t_last - t0) within k dt of
  // k (t_td + W - t0); impulse sum F_n dt against k / 2 ((t_td + W - t0)^2 - (t_td - t0)^2)
  // within k dt W (right samples of a rising ramp); rise time 0.8 peak / k (exact for the
  // sampled peak).
  const double k = 1e5, t0 = 0.1, dt = 1e-4;
  const LandingParameters params{12.5, 0.05};
  const auto landings = detect(
      params, dt, 3000, [&](double t) { return t > t0 ? k * (t - t0) : 0.0; },
      [](double t) { return 3.0 * std::sin(2 * M_PI * 10 * t); });
  ASSERT_EQ(landings.size(), 1u);
  const Landing& l = landings[0];
  const double t_td = t0 + params.threshold / k, end = t_td + params.window - t0;
  const double impulse = 0.5 * k * (end * end - (t_td - t0) * (t_td - t0));
  std::printf("ramp: touchdown %.9f s (closed form %.9f), peak %.3f N (%.3f), impulse %.5f N s "
              "(%.5f, tol %.3f), rise time %.6f s (0.8 peak / k = %.6f), peak |a| %.6f (3), "
              "window %.6f s\n",
              l.time, t_td, l.peak_force, k * end, l.impulse, impulse, k * dt * params.window,
              l.rise_time, 0.8 * l.peak_force / k, l.peak_acceleration, l.window);
  EXPECT_NEAR(l.time, t_td, 1e-12);
  EXPECT_LE(l.peak_force, k * end + 1e-9);
  EXPECT_GT(l.peak_force, k * end - k * dt);
  EXPECT_NEAR(l.impulse, impulse, k * dt * params.window);
  EXPECT_NEAR(l.rise_time, 0.8 * l.peak_force / k, 1e-12);
  EXPECT_NEAR(l.rise_time, 0.8 * end, 0.8 * dt);
  EXPECT_NEAR(l.peak_acceleration, 3.0, 1e-9); // |3 sin(2 pi 10 t)| peaks at t = 0.125 s
  EXPECT_NEAR(l.window, params.window, dt);
}

TEST(LandingDetector, HalfSineAgainstClosedForms) {
  // F = P sin(pi (t - t0) / T): touchdown t0 + T / pi asin(F_th / P); impulse over the window
  // (past touchdown) 2 P T / pi - P T / pi (1 - sqrt(1 - (F_th / P)^2)) (the window holds the
  // whole pulse), tolerance 2 F_th dt (the first sample's step starts before touchdown);
  // rise time T / pi (asin 0.9 - asin 0.1), linear interpolation error ~ dt^2 F'' / (8 F').
  const double P = 2000, T = 0.02, t0 = 0.2, dt = 1e-5, mass = 50;
  const LandingParameters params{10.0, 0.05};
  const auto force = [&](double t) { return half_sine(t, P, t0, T); };
  const auto landings =
      detect(params, dt, 40000, force, [&](double t) { return -force(t) / mass; });
  ASSERT_EQ(landings.size(), 1u);
  const Landing& l = landings[0];
  const double ratio = params.threshold / P;
  const double t_td = t0 + T / M_PI * std::asin(ratio);
  const double impulse = 2 * P * T / M_PI - P * T / M_PI * (1 - std::sqrt(1 - ratio * ratio));
  const double rise = T / M_PI * (std::asin(0.9) - std::asin(0.1));
  std::printf("half sine: touchdown %.9f s (closed form %.9f), impulse %.7f N s (%.7f; 2 P T / "
              "pi = %.7f), peak %.6f N (%.0f) at %.6f s, rise time %.9f s (%.9f), peak |a| "
              "%.6f (%.6f)\n",
              l.time, t_td, l.impulse, impulse, 2 * P * T / M_PI, l.peak_force, P, l.peak_time,
              l.rise_time, rise, l.peak_acceleration, P / mass);
  EXPECT_NEAR(l.time, t_td, 1e-9);
  EXPECT_NEAR(l.impulse, impulse, 2 * params.threshold * dt);
  EXPECT_NEAR(l.peak_force, P, P * std::pow(M_PI * dt / T, 2) / 2);
  EXPECT_NEAR(l.peak_time, t0 + T / 2, dt);
  EXPECT_NEAR(l.rise_time, rise, 1e-7);
  EXPECT_NEAR(l.peak_acceleration, P / mass, 1e-3);
  EXPECT_NEAR(l.window, params.window, dt);
}

TEST(LandingDetector, ArmingBouncesAndRunEnd) {
  const double dt = 1e-4, P = 1000, T = 0.01;
  const LandingParameters params{5.0, 0.05};
  // Loaded from the first sample until 0.1 s (no landing: never seen below the threshold),
  // then a pulse at 0.3 s with a bounce 20 ms later (one landing: the bounce is in its
  // window, impulse of both pulses 2 * 2 P T / pi), a pulse at 0.6 s (a second landing) and
  // one at 0.98 s that the run (1 s) cuts 20 ms into its window.
  const auto force = [&](double t) {
    return (t < 0.1 ? 500.0 : 0.0) + half_sine(t, P, 0.3, T) + half_sine(t, P, 0.32, T) +
           half_sine(t, P, 0.6, T) + half_sine(t, P, 0.98, T);
  };
  const auto landings = detect(params, dt, 10000, force, [](double) { return 0.0; });
  ASSERT_EQ(landings.size(), 3u);
  // Impulse of a half-sine sampled every dt: 2 P T / pi within (2 P T / pi) (pi dt / T)^2 / 12
  // (the sum of right samples = trapezoids; the kinks at the ends make it second order),
  // tolerance twice that per pulse plus F_th dt (the part before touchdown).
  const double pulse = 2 * P * T / M_PI;
  const double tolerance = 2 * pulse * std::pow(M_PI * dt / T, 2) / 12;
  std::printf("landings at %.4f, %.4f, %.4f s; impulses %.4f, %.4f N s (one pulse %.4f); last "
              "window %.4f s\n",
              landings[0].time, landings[1].time, landings[2].time, landings[0].impulse,
              landings[1].impulse, pulse, landings[2].window);
  EXPECT_NEAR(landings[0].time, 0.3, 1e-4);
  EXPECT_NEAR(landings[0].impulse, 2 * pulse, 2 * tolerance + params.threshold * dt);
  EXPECT_NEAR(landings[1].time, 0.6, 1e-4);
  EXPECT_NEAR(landings[1].impulse, pulse, tolerance + params.threshold * dt);
  EXPECT_NEAR(landings[2].time, 0.98, 1e-4);
  EXPECT_NEAR(landings[2].window, 0.9999 - landings[2].time, 1e-9);
  EXPECT_NEAR(landings[2].impulse, pulse, tolerance + params.threshold * dt);
}

TEST(LandingDetector, WritesLandingsCsvInTimeOrder) {
  std::vector<Landing> right(2), left(1);
  right[0].time = 0.5;
  right[1].time = 2.0;
  left[0].time = 1.0;
  left[0].peak_force = 1234.5;
  const std::filesystem::path path =
      std::filesystem::temp_directory_path() / "plantar_test_landings.csv";
  write_landings_csv(right, left, path);
  std::ifstream in(path);
  std::string header, row;
  std::getline(in, header);
  EXPECT_EQ(header, "foot,t,impulse,peak_force,peak_time,rise_time,peak_az_filtered,window");
  std::vector<std::pair<double, double>> foot_time;
  while (std::getline(in, row)) {
    std::istringstream fields(row);
    double foot, t;
    char comma;
    fields >> foot >> comma >> t;
    foot_time.emplace_back(foot, t);
    if (foot == 1) {
      EXPECT_NE(row.find("1234.5"), std::string::npos);
    }
  }
  ASSERT_EQ(foot_time.size(), 3u);
  EXPECT_EQ(foot_time[0], std::make_pair(0.0, 0.5));
  EXPECT_EQ(foot_time[1], std::make_pair(1.0, 1.0));
  EXPECT_EQ(foot_time[2], std::make_pair(0.0, 2.0));
  std::filesystem::remove(path);
}

TEST(LandingDetector, BadParametersAreRejected) {
  EXPECT_THROW(LandingDetector({0.0, 0.05}, 1e-3, 10), std::invalid_argument);
  EXPECT_THROW(LandingDetector({1.0, 0.0}, 1e-3, 10), std::invalid_argument);
  EXPECT_THROW(LandingDetector({1.0, 0.05}, 0.0, 10), std::invalid_argument);
}
