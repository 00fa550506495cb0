#pragma once
// Shared helpers of the multibody tests.

#include "multibody/model.h"

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <algorithm>
#include <random>
#include <string>

namespace plantar::multibody::test {

inline std::string model_path(const std::string& relative) {
  return std::string(PLANTAR_SOURCE_DIR) + "/models/" + relative;
}

/// Random configuration: base position in [-1, 1]^3, random unit quaternion, each 1-DoF
/// joint uniform in its limits intersected with [-1.5, 1.5].
inline Eigen::VectorXd random_configuration(const Model& model, std::mt19937& rng) {
  std::uniform_real_distribution<double> uniform(-1.0, 1.0);
  Eigen::VectorXd q = model.neutral_configuration();
  for (int i = 1; i < model.n_bodies; ++i) {
    const int iq = model.idx_q[i];
    if (model.joint_type[i] == JointType::FreeFlyer) {
      for (int k = 0; k < 3; ++k) {
        q[iq + k] = uniform(rng);
      }
      Eigen::Vector4d quat(uniform(rng), uniform(rng), uniform(rng), uniform(rng));
      q.segment<4>(iq + 3) = quat.normalized();
    } else {
      const double lo = std::max(model.lower_position_limit[iq], -1.5);
      const double hi = std::min(model.upper_position_limit[iq], 1.5);
      q[iq] = lo + 0.5 * (uniform(rng) + 1.0) * (hi - lo);
    }
  }
  return q;
}

inline Eigen::VectorXd random_vector(int n, std::mt19937& rng) {
  std::uniform_real_distribution<double> uniform(-1.0, 1.0);
  Eigen::VectorXd v(n);
  for (int k = 0; k < n; ++k) {
    v[k] = uniform(rng);
  }
  return v;
}

} // namespace plantar::multibody::test
