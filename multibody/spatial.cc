#include "multibody/spatial.h"

#include <cmath>

namespace plantar::multibody {

SE3 exp6(const Vector6d& twist) {
  const Eigen::Vector3d v = twist.head<3>();
  const Eigen::Vector3d w = twist.tail<3>();
  const double t2 = w.squaredNorm();
  const double t = std::sqrt(t2);
  const Eigen::Matrix3d wx = skew(w);
  double a; // (1 - cos t) / t^2
  double b; // (t - sin t) / t^3
  if (t < 1e-4) {
    // Taylor series, error below 1e-17 for t < 1e-4.
    a = 0.5 - t2 / 24.0;
    b = 1.0 / 6.0 - t2 / 120.0;
  } else {
    a = (1.0 - std::cos(t)) / t2;
    b = (t - std::sin(t)) / (t2 * t);
  }
  SE3 out;
  out.rotation = exp3_quaternion(w).toRotationMatrix();
  out.translation = v + a * (wx * v) + b * (wx * (wx * v));
  return out;
}

Eigen::Quaterniond exp3_quaternion(const Eigen::Vector3d& w) {
  const double t = w.norm();
  const double half = 0.5 * t;
  // sin(t/2)/t with its Taylor series near 0.
  const double s = t < 1e-4 ? 0.5 - t * t / 48.0 : std::sin(half) / t;
  return Eigen::Quaterniond(std::cos(half), s * w.x(), s * w.y(), s * w.z());
}

Eigen::Vector3d log3(const Eigen::Matrix3d& rotation) {
  const Eigen::Quaterniond quat(rotation);
  const Eigen::Vector3d v = quat.vec();
  const double s = v.norm();
  const double c = std::abs(quat.w());
  const double sign = quat.w() < 0.0 ? -1.0 : 1.0;
  // 2 atan2(s, c) / s with its Taylor series 2/c (1 - s^2 / (3 c^2)) for s << c (theta < 2e-4).
  const double scale =
      s < 1e-4 * c ? 2.0 / c * (1.0 - s * s / (3.0 * c * c)) : 2.0 * std::atan2(s, c) / s;
  return sign * scale * v;
}

Eigen::Matrix3d log3_left_jacobian_inverse(const Eigen::Vector3d& w) {
  const double t2 = w.squaredNorm();
  const double t = std::sqrt(t2);
  // 1/t^2 - cot(t/2)/(2 t), Taylor series below t = 1e-2 (truncation error below 1e-18).
  const double b = t < 1e-2 ? 1.0 / 12.0 + t2 / 720.0 + t2 * t2 / 30240.0
                            : 1.0 / t2 - std::cos(0.5 * t) / (2.0 * t * std::sin(0.5 * t));
  const Eigen::Matrix3d wx = skew(w);
  return Eigen::Matrix3d::Identity() - 0.5 * wx + b * (wx * wx);
}

} // namespace plantar::multibody
