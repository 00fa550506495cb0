// The accelerometer's second-order Butterworth low-pass (issue 23): its gain against the
// closed form |H(e^{jwT})| = 1 / sqrt(1 + (tan(pi f T) / tan(pi f_c T))^4), its step response,
// bad cut-offs.
#include "apps/butterworth_low_pass.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <gtest/gtest.h>
#include <limits>
#include <stdexcept>
#include <string>

using namespace plantar::app;

namespace {

/// Amplitude of the filter's steady-state response to sin(2 pi f t), by projecting the output
/// on sin and cos over the second second (an integer number of periods; the transient decays
/// as exp(-zeta w_c t), below 1e-100 after 1 s).
double measured_gain(const ButterworthLowPass& f, double frequency, double period) {
  ButterworthState state;
  const int n = static_cast<int>(std::lround(1.0 / period));
  double s = 0, c = 0;
  for (int i = 0; i < 2 * n; ++i) {
    const double phase = 2 * M_PI * frequency * i * period;
    const double y = filter(f, state, std::sin(phase));
    if (i >= n) {
      s += y * std::sin(phase);
      c += y * std::cos(phase);
    }
  }
  return 2.0 / n * std::hypot(s, c);
}

} // namespace

TEST(ButterworthLowPass, GainMatchesTheClosedForm) {
  const double dt = 1e-3, cutoff = 100;
  const ButterworthLowPass f = make_butterworth_low_pass(cutoff, dt, "test");
  double max_error = 0;
  for (const double frequency : {1.0, 10.0, 50.0, 100.0, 150.0, 200.0, 300.0, 400.0}) {
    const double closed =
        1.0 /
        std::sqrt(1.0 +
                  std::pow(std::tan(M_PI * frequency * dt) / std::tan(M_PI * cutoff * dt), 4));
    const double gain = measured_gain(f, frequency, dt);
    std::printf("f = %5.0f Hz: gain %.12f, closed form %.12f\n", frequency, gain, closed);
    max_error = std::max(max_error, std::abs(gain - closed));
  }
  std::printf("max |gain - closed form| = %.2e (tol 1e-9)\n", max_error);
  EXPECT_LT(max_error, 1e-9);
  EXPECT_NEAR(measured_gain(f, cutoff, dt), 1.0 / std::sqrt(2.0), 1e-9); // -3 dB at f_c
  // DC gain 1: (b0 + b1 + b2) / (1 + a1 + a2).
  EXPECT_NEAR((f.b0 + f.b1 + f.b2) / (1 + f.a1 + f.a2), 1.0, 1e-14);
}

TEST(ButterworthLowPass, StepResponseSettlesToOne) {
  // Analog second-order Butterworth (zeta = 1/sqrt 2): overshoot exp(-pi) = 4.32 %; the
  // bilinear map at f_c T = 0.1 changes it a little (tolerance 1 point).
  const double dt = 1e-3;
  const ButterworthLowPass f = make_butterworth_low_pass(100, dt, "test");
  ButterworthState state;
  double y = 0, peak = 0;
  for (int i = 0; i < 200; ++i) {
    y = filter(f, state, 1.0);
    peak = std::max(peak, y);
  }
  std::printf("step: y(200 ms) - 1 = %.2e (tol 1e-9), overshoot %.3f %% (analog %.3f %%)\n", y - 1,
              100 * (peak - 1), 100 * std::exp(-M_PI));
  EXPECT_NEAR(y, 1.0, 1e-9);
  EXPECT_NEAR(peak - 1, std::exp(-M_PI), 0.01);
  // Cut-off 0: the raw signal.
  const ButterworthLowPass raw = make_butterworth_low_pass(0, dt, "test");
  ButterworthState raw_state;
  for (const double x : {0.0, 3.5, -2.0, 7.25})
    EXPECT_EQ(filter(raw, raw_state, x), x);
}

TEST(ButterworthLowPass, BadCutoffIsRejected) {
  const double nan = std::numeric_limits<double>::quiet_NaN();
  for (const double cutoff : {-1.0, 500.0, 1e4, nan}) {
    try {
      make_butterworth_low_pass(cutoff, 1e-3, "Output/Accelerometer bandwidth");
      ADD_FAILURE() << cutoff << " Hz accepted at dt = 1 ms";
    } catch (const std::invalid_argument& e) {
      const std::string what = e.what();
      std::printf("%s\n", e.what());
      EXPECT_NE(what.find("Output/Accelerometer bandwidth"), std::string::npos);
      EXPECT_NE(what.find("[0, 500) Hz"), std::string::npos);
    }
  }
  EXPECT_NO_THROW(make_butterworth_low_pass(499, 1e-3, "x"));
  EXPECT_THROW(make_butterworth_low_pass(10, 0.0, "x"), std::invalid_argument);
}
