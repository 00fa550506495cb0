#include "multibody/crba.h"

#include "multibody/kinematics.h"

namespace plantar::multibody {

const Eigen::MatrixXd& crba(const Model& model, Data& data,
                            const Eigen::Ref<const Eigen::VectorXd>& q) {
  forward_kinematics(model, data, q);
  return crba_from_placements(model, data);
}

const Eigen::MatrixXd& crba_from_placements(const Model& model, Data& data) {
  for (int i = 0; i < model.n_bodies; ++i) {
    data.composite[i] = model.inertia[i];
  }
  for (int i = model.n_bodies - 1; i > 1; --i) {
    const int parent = model.parent[i];
    if (parent > 0) {
      data.composite[parent] += data.composite[i].transformed(data.liMi[i]);
    }
  }
  Eigen::MatrixXd& m = data.mass_matrix;
  for (int i = model.n_bodies - 1; i > 0; --i) {
    const auto& si = model.motion_subspace[i];
    const int iv = model.idx_v[i];
    const int nvi = model.nv_joint[i];
    if (nvi == 1) {
      // Single-DoF joint (all but the free base): one force carried up the tree.
      Vector6d force = data.composite[i] * Vector6d(si.col(0));
      m(iv, iv) = si.col(0).dot(force);
      for (int j = i; model.parent[j] > 0;) {
        force = data.liMi[j].act_force(force);
        j = model.parent[j];
        const int jv = model.idx_v[j];
        const auto& sj = model.motion_subspace[j];
        for (int k = 0; k < model.nv_joint[j]; ++k) {
          m(jv + k, iv) = m(iv, jv + k) = sj.col(k).dot(force);
        }
      }
      continue;
    }
    // F = I^c_i S_i, one force per column, carried up the tree.
    Matrix6Xmax6 force(6, nvi);
    for (int k = 0; k < nvi; ++k) {
      force.col(k) = data.composite[i] * Vector6d(si.col(k));
    }
    m.block(iv, iv, nvi, nvi).noalias() = si.transpose() * force;
    int j = i;
    while (model.parent[j] > 0) {
      for (int k = 0; k < nvi; ++k) {
        force.col(k) = data.liMi[j].act_force(Vector6d(force.col(k)));
      }
      j = model.parent[j];
      const int jv = model.idx_v[j];
      const int nvj = model.nv_joint[j];
      m.block(jv, iv, nvj, nvi).noalias() = model.motion_subspace[j].transpose() * force;
      m.block(iv, jv, nvi, nvj) = m.block(jv, iv, nvj, nvi).transpose();
    }
  }
  return m;
}

} // namespace plantar::multibody
