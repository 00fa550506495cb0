#include "multibody/sensors/force_torque_sensor.h"

#include <stdexcept>

namespace plantar::multibody::sensors {

Vector6d contact_wrench(const Eigen::Ref<const Eigen::Matrix3Xd>& points,
                        const Eigen::Ref<const Eigen::Matrix3Xd>& forces) {
  if (points.cols() != forces.cols())
    throw std::invalid_argument("contact_wrench: points and forces differ in number");
  Vector6d wrench = Vector6d::Zero();
  for (Eigen::Index k = 0; k < points.cols(); ++k) {
    wrench.head<3>() += forces.col(k);
    wrench.tail<3>() += points.col(k).cross(forces.col(k));
  }
  return wrench;
}

Vector6d wrench_at_sensor(const SE3& sensor, const Vector6d& wrench) {
  Vector6d out;
  const Eigen::Vector3d f = wrench.head<3>();
  out.head<3>() = sensor.rotation.transpose() * f;
  out.tail<3>() = sensor.rotation.transpose() * (wrench.tail<3>() - sensor.translation.cross(f));
  return out;
}

} // namespace plantar::multibody::sensors
