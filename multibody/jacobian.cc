#include "multibody/jacobian.h"

#include "multibody/kinematics.h"

namespace plantar::multibody {

void body_jacobian_world(const Model& model, const Data& data, int body,
                         Eigen::Ref<Eigen::MatrixXd> jacobian) {
  check_size(jacobian.rows(), 6, "body_jacobian_world: rows");
  check_size(jacobian.cols(), model.nv, "body_jacobian_world: cols");
  jacobian.setZero();
  for (int j = body; j > 0; j = model.parent[j]) {
    const auto& s = model.motion_subspace[j];
    for (int k = 0; k < model.nv_joint[j]; ++k) {
      jacobian.col(model.idx_v[j] + k) = data.oMi[j].act_motion(Vector6d(s.col(k)));
    }
  }
}

void point_jacobian(const Model& model, const Data& data, int body, const Eigen::Vector3d& point,
                    Eigen::Ref<Eigen::MatrixXd> jacobian) {
  check_size(jacobian.rows(), 3, "point_jacobian: rows");
  check_size(jacobian.cols(), model.nv, "point_jacobian: cols");
  jacobian.setZero();
  const Eigen::Vector3d p_world = data.oMi[body].act_point(point);
  for (int j = body; j > 0; j = model.parent[j]) {
    const auto& s = model.motion_subspace[j];
    for (int k = 0; k < model.nv_joint[j]; ++k) {
      const Vector6d col = data.oMi[j].act_motion(Vector6d(s.col(k)));
      jacobian.col(model.idx_v[j] + k) = col.head<3>() + col.tail<3>().cross(p_world);
    }
  }
}

void body_origin_jacobian(const Model& model, const Data& data, int body,
                          Eigen::Ref<Eigen::MatrixXd> jacobian) {
  check_size(jacobian.rows(), 6, "body_origin_jacobian: rows");
  check_size(jacobian.cols(), model.nv, "body_origin_jacobian: cols");
  jacobian.setZero();
  const Eigen::Vector3d& origin = data.oMi[body].translation;
  for (int j = body; j > 0; j = model.parent[j]) {
    const auto& s = model.motion_subspace[j];
    const SE3& placement = data.oMi[j];
    const Eigen::Vector3d lever = origin - placement.translation;
    for (int k = 0; k < model.nv_joint[j]; ++k) {
      auto col = jacobian.col(model.idx_v[j] + k);
      const Eigen::Vector3d w = placement.rotation * s.col(k).tail<3>();
      col.head<3>() = placement.rotation * s.col(k).head<3>() + w.cross(lever);
      col.tail<3>() = w;
    }
  }
}

void frame_jacobian(const Model& model, const Data& data, int frame,
                    Eigen::Ref<Eigen::MatrixXd> jacobian) {
  check_size(jacobian.rows(), 6, "frame_jacobian: rows");
  check_size(jacobian.cols(), model.nv, "frame_jacobian: cols");
  jacobian.setZero();
  const Frame& fr = model.frames[frame];
  const Eigen::Vector3d p_world = data.oMi[fr.body].act_point(fr.placement.translation);
  for (int j = fr.body; j > 0; j = model.parent[j]) {
    const auto& s = model.motion_subspace[j];
    for (int k = 0; k < model.nv_joint[j]; ++k) {
      const Vector6d col = data.oMi[j].act_motion(Vector6d(s.col(k)));
      jacobian.col(model.idx_v[j] + k).head<3>() = col.head<3>() + col.tail<3>().cross(p_world);
      jacobian.col(model.idx_v[j] + k).tail<3>() = col.tail<3>();
    }
  }
}

Eigen::Vector3d point_drift_acceleration(const Model& model, const Data& data, int body,
                                         const Eigen::Vector3d& point) {
  const Vector6d& vel = data.v[body];
  const Vector6d& acc = data.a[body];
  const Eigen::Vector3d w = vel.tail<3>();
  const Eigen::Vector3d v_point = vel.head<3>() + w.cross(point);
  const Eigen::Vector3d a_local = acc.head<3>() + acc.tail<3>().cross(point) + w.cross(v_point);
  return data.oMi[body].rotation * a_local;
}

Vector6d frame_drift_acceleration(const Model& model, const Data& data, int frame) {
  const Frame& fr = model.frames[frame];
  Vector6d out;
  out.head<3>() = point_drift_acceleration(model, data, fr.body, fr.placement.translation);
  out.tail<3>() = data.oMi[fr.body].rotation * data.a[fr.body].tail<3>();
  return out;
}

} // namespace plantar::multibody
