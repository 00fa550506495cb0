#include "multibody/rnea.h"

#include "multibody/kinematics.h"

namespace plantar::multibody {

const Eigen::VectorXd& rnea(const Model& model, Data& data,
                            const Eigen::Ref<const Eigen::VectorXd>& q,
                            const Eigen::Ref<const Eigen::VectorXd>& v,
                            const Eigen::Ref<const Eigen::VectorXd>& a) {
  check_size(q.size(), model.nq, "rnea: q");
  check_size(v.size(), model.nv, "rnea: v");
  check_size(a.size(), model.nv, "rnea: a");
  data.v[0].setZero();
  data.a[0].head<3>() = -model.gravity;
  data.a[0].tail<3>().setZero();
  data.oMi[0] = SE3();
  for (int i = 1; i < model.n_bodies; ++i) {
    const int parent = model.parent[i];
    const auto& s = model.motion_subspace[i];
    const int iv = model.idx_v[i];
    const int nvi = model.nv_joint[i];
    data.liMi[i] = model.joint_placement[i] * joint_motion(model, i, q);
    data.oMi[i] = data.oMi[parent] * data.liMi[i];
    Vector6d vj;
    vj.noalias() = s * v.segment(iv, nvi);
    data.v[i] = data.liMi[i].act_inv_motion(data.v[parent]) + vj;
    data.a[i] = data.liMi[i].act_inv_motion(data.a[parent]) + cross_motion(data.v[i], vj);
    data.a[i].noalias() += s * a.segment(iv, nvi);
    const Inertia& inertia = model.inertia[i];
    data.f[i] = inertia * data.a[i] + cross_force(data.v[i], inertia * data.v[i]);
  }
  for (int i = model.n_bodies - 1; i > 0; --i) {
    data.tau.segment(model.idx_v[i], model.nv_joint[i]).noalias() =
        model.motion_subspace[i].transpose() * data.f[i];
    const int parent = model.parent[i];
    if (parent > 0) {
      data.f[parent] += data.liMi[i].act_force(data.f[i]);
    }
  }
  return data.tau;
}

const Eigen::VectorXd& nonlinear_effects(const Model& model, Data& data,
                                         const Eigen::Ref<const Eigen::VectorXd>& q,
                                         const Eigen::Ref<const Eigen::VectorXd>& v) {
  rnea(model, data, q, v, data.zero_nv);
  data.bias = data.tau;
  return data.bias;
}

const Eigen::VectorXd& gravity_torques(const Model& model, Data& data,
                                       const Eigen::Ref<const Eigen::VectorXd>& q) {
  rnea(model, data, q, data.zero_nv, data.zero_nv);
  data.bias = data.tau;
  return data.bias;
}

} // namespace plantar::multibody
