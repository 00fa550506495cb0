#pragma once
// Second-order Butterworth low-pass filter, discretised by the bilinear transform with
// pre-warping: the simulated accelerometer's bandwidth (Output/Accelerometer bandwidth).

namespace plantar::app {

/// Coefficients (constant) of y_n = b0 x_n + b1 x_n-1 + b2 x_n-2 - a1 y_n-1 - a2 y_n-2.
/// Analog prototype H(s) = w_c^2 / (s^2 + sqrt(2) w_c s + w_c^2), s = (2 / T) (1 - z^-1) /
/// (1 + z^-1), w_c pre-warped so that the digital cut-off is f_c: with K = tan(pi f_c T),
///   b0 = b2 = K^2 / D, b1 = 2 b0, a1 = 2 (K^2 - 1) / D, a2 = (1 - sqrt(2) K + K^2) / D,
///   D = 1 + sqrt(2) K + K^2.
/// Its gain is |H(e^{j 2 pi f T})| = 1 / sqrt(1 + (tan(pi f T) / K)^4): 1 at f = 0,
/// 1/sqrt(2) at f_c, 0 at the Nyquist frequency 1 / (2 T).
struct ButterworthLowPass {
  double b0 = 1, b1 = 0, b2 = 0, a1 = 0, a2 = 0; ///< default: pass-through
};

/// The filter's memory (x_n-1, x_n-2, y_n-1, y_n-2); zero: a signal at rest at 0.
struct ButterworthState {
  double x1 = 0, x2 = 0, y1 = 0, y2 = 0;
};

/// The filter of cut-off @p cutoff [Hz] for the sample period @p period [s]. @p cutoff = 0
/// gives the pass-through (y = x). Throws std::invalid_argument naming @p parameter, the value
/// and the allowed range [0, 1 / (2 period)) if cutoff is negative or not below the Nyquist
/// frequency, or if period <= 0.
ButterworthLowPass make_butterworth_low_pass(double cutoff, double period, const char* parameter);

/// One sample: returns y_n for the input x_n and advances @p state. No allocation.
inline double filter(const ButterworthLowPass& f, ButterworthState& state, double x) {
  const double y = f.b0 * x + f.b1 * state.x1 + f.b2 * state.x2 - f.a1 * state.y1 - f.a2 * state.y2;
  state.x2 = state.x1;
  state.x1 = x;
  state.y2 = state.y1;
  state.y1 = y;
  return y;
}

} // namespace plantar::app
