#include "multibody/configuration.h"

#include "multibody/kinematics.h"
#include "multibody/spatial.h"

namespace plantar::multibody {

void integrate(const Model& model, const Eigen::Ref<const Eigen::VectorXd>& q,
               const Eigen::Ref<const Eigen::VectorXd>& v, double dt,
               Eigen::Ref<Eigen::VectorXd> q_out) {
  check_size(q.size(), model.nq, "integrate: q");
  check_size(v.size(), model.nv, "integrate: v");
  check_size(q_out.size(), model.nq, "integrate: q_out");
  for (int i = 1; i < model.n_bodies; ++i) {
    const int iq = model.idx_q[i];
    const int iv = model.idx_v[i];
    if (model.joint_type[i] == JointType::FreeFlyer) {
      Eigen::Quaterniond quat(q[iq + 6], q[iq + 3], q[iq + 4], q[iq + 5]);
      quat.normalize();
      const Vector6d twist = dt * v.segment<6>(iv);
      const SE3 step = exp6(twist);
      const Eigen::Vector3d position = q.segment<3>(iq) + quat * step.translation;
      Eigen::Quaterniond next = quat * exp3_quaternion(twist.tail<3>());
      next.normalize();
      q_out.segment<3>(iq) = position;
      q_out[iq + 3] = next.x();
      q_out[iq + 4] = next.y();
      q_out[iq + 5] = next.z();
      q_out[iq + 6] = next.w();
    } else {
      q_out[iq] = q[iq] + dt * v[iv];
    }
  }
}

void normalize_configuration(const Model& model, Eigen::Ref<Eigen::VectorXd> q) {
  check_size(q.size(), model.nq, "normalize_configuration: q");
  for (int i = 1; i < model.n_bodies; ++i) {
    if (model.joint_type[i] == JointType::FreeFlyer) {
      q.segment<4>(model.idx_q[i] + 3).normalize();
    }
  }
}

} // namespace plantar::multibody
