#pragma once
// One sensor's signal path: a delay of k control periods, a constant bias and white Gaussian
// noise (seeded), applied to a vector of n channels:
//   y_n = x_{n-k} + b + sigma . w_n,   w_n ~ N(0, I) (std::mt19937 seeded once),
// x_{n-k} replaced by the first sample x_0 while fewer than k samples were stored.
// Sized by the constructor; measure() allocates nothing.

#include <Eigen/Core>

#include <cstdint>
#include <random>

namespace plantar::multibody::sensors {

class SensorChannel {
public:
  SensorChannel() = default;
  /// @p noise (sigma) and @p bias: per channel, size n, in the channel's unit; @p delay: k >= 0
  /// calls of measure(). Throws std::invalid_argument for a negative delay or sigma, or sizes
  /// that differ.
  SensorChannel(const Eigen::VectorXd& noise, const Eigen::VectorXd& bias, int delay,
                std::uint32_t seed);
  int size() const { return static_cast<int>(bias_.size()); }
  int delay() const { return delay_; }
  /// Stores @p truth (size n) and returns the measurement y_n (valid until the next call).
  const Eigen::VectorXd& measure(const Eigen::Ref<const Eigen::VectorXd>& truth);

private:
  Eigen::VectorXd noise_, bias_, output_;
  Eigen::MatrixXd history_; ///< n x (k + 1) ring buffer
  int delay_ = 0, stored_ = 0, head_ = 0;
  std::mt19937 rng_;
  std::normal_distribution<double> normal_{0.0, 1.0};
};

} // namespace plantar::multibody::sensors
