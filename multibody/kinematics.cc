#include "multibody/kinematics.h"

#include <stdexcept>
#include <string>

namespace plantar::multibody {

void check_size(Eigen::Index size, Eigen::Index expected, const char* what) {
  if (size != expected) {
    throw std::invalid_argument(std::string(what) + ": wrong size, expected " +
                                std::to_string(expected) + ", got " + std::to_string(size));
  }
}

SE3 joint_motion(const Model& model, int joint, const Eigen::Ref<const Eigen::VectorXd>& q) {
  const int iq = model.idx_q[joint];
  switch (model.joint_type[joint]) {
  case JointType::FreeFlyer: {
    Eigen::Quaterniond quat(q[iq + 6], q[iq + 3], q[iq + 4], q[iq + 5]);
    quat.normalize();
    return SE3(quat.toRotationMatrix(), q.segment<3>(iq));
  }
  case JointType::Revolute:
    return SE3(axis_rotation(model.joint_axis[joint], q[iq]), Eigen::Vector3d::Zero());
  case JointType::Prismatic:
    return SE3(Eigen::Matrix3d::Identity(), model.joint_axis[joint] * q[iq]);
  default:
    return SE3();
  }
}

void forward_kinematics(const Model& model, Data& data,
                        const Eigen::Ref<const Eigen::VectorXd>& q) {
  check_size(q.size(), model.nq, "forward_kinematics: q");
  data.oMi[0] = SE3();
  for (int i = 1; i < model.n_bodies; ++i) {
    data.liMi[i] = model.joint_placement[i] * joint_motion(model, i, q);
    data.oMi[i] = data.oMi[model.parent[i]] * data.liMi[i];
  }
}

void forward_kinematics(const Model& model, Data& data, const Eigen::Ref<const Eigen::VectorXd>& q,
                        const Eigen::Ref<const Eigen::VectorXd>& v) {
  check_size(v.size(), model.nv, "forward_kinematics: v");
  forward_kinematics(model, data, q);
  data.v[0].setZero();
  for (int i = 1; i < model.n_bodies; ++i) {
    const auto& s = model.motion_subspace[i];
    data.v[i] = data.liMi[i].act_inv_motion(data.v[model.parent[i]]);
    data.v[i].noalias() += s * v.segment(model.idx_v[i], model.nv_joint[i]);
  }
}

void forward_kinematics(const Model& model, Data& data, const Eigen::Ref<const Eigen::VectorXd>& q,
                        const Eigen::Ref<const Eigen::VectorXd>& v,
                        const Eigen::Ref<const Eigen::VectorXd>& a) {
  check_size(a.size(), model.nv, "forward_kinematics: a");
  forward_kinematics(model, data, q, v);
  data.a[0].setZero();
  for (int i = 1; i < model.n_bodies; ++i) {
    const auto& s = model.motion_subspace[i];
    Vector6d vj;
    vj.noalias() = s * v.segment(model.idx_v[i], model.nv_joint[i]);
    data.a[i] = data.liMi[i].act_inv_motion(data.a[model.parent[i]]) + cross_motion(data.v[i], vj);
    data.a[i].noalias() += s * a.segment(model.idx_v[i], model.nv_joint[i]);
  }
}

SE3 frame_placement(const Model& model, const Data& data, int frame) {
  const Frame& fr = model.frames[frame];
  return data.oMi[fr.body] * fr.placement;
}

} // namespace plantar::multibody
