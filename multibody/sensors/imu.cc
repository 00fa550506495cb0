#include "multibody/sensors/imu.h"

#include "multibody/jacobian.h"

namespace plantar::multibody::sensors {

ImuReading read_imu(const Model& model, const Data& data, int frame) {
  const Frame& f = model.frames[frame];
  const SE3& body = data.oMi[f.body];
  ImuReading out;
  out.orientation = body.rotation * f.placement.rotation;
  out.angular_velocity = f.placement.rotation.transpose() * data.v[f.body].tail<3>();
  const Eigen::Vector3d acceleration =
      point_drift_acceleration(model, data, f.body, f.placement.translation);
  out.linear_acceleration = out.orientation.transpose() * (acceleration - model.gravity);
  return out;
}

} // namespace plantar::multibody::sensors
