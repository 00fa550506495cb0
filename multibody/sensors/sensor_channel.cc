#include "multibody/sensors/sensor_channel.h"

#include <stdexcept>
#include <string>

namespace plantar::multibody::sensors {

SensorChannel::SensorChannel(const Eigen::VectorXd& noise, const Eigen::VectorXd& bias, int delay,
                             std::uint32_t seed)
    : noise_(noise), bias_(bias), output_(bias.size()), delay_(delay), rng_(seed) {
  if (noise.size() != bias.size())
    throw std::invalid_argument("SensorChannel: noise has " + std::to_string(noise.size()) +
                                " channels, bias " + std::to_string(bias.size()));
  if (delay < 0)
    throw std::invalid_argument("SensorChannel: delay = " + std::to_string(delay) +
                                " control periods, must be >= 0");
  if ((noise.array() < 0).any())
    throw std::invalid_argument("SensorChannel: a noise standard deviation is negative");
  history_.setZero(bias.size(), delay + 1);
  output_.setZero();
}

const Eigen::VectorXd& SensorChannel::measure(const Eigen::Ref<const Eigen::VectorXd>& truth) {
  const int slots = delay_ + 1;
  if (stored_ == 0)
    for (int k = 0; k < slots; ++k)
      history_.col(k) = truth; // x_0 stands for the samples before it
  else
    history_.col(head_) = truth;
  ++stored_;
  // The oldest slot is the one written next: k calls ago.
  head_ = (head_ + 1) % slots;
  output_ = history_.col(head_) + bias_;
  for (int i = 0; i < output_.size(); ++i)
    if (noise_[i] > 0)
      output_[i] += noise_[i] * normal_(rng_);
  return output_;
}

} // namespace plantar::multibody::sensors
