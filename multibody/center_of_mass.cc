#include "multibody/center_of_mass.h"

#include <stdexcept>

namespace plantar::multibody {

const Eigen::Vector3d& center_of_mass(const Model& model, Data& data) {
  double mass = 0.0;
  Eigen::Vector3d sum = Eigen::Vector3d::Zero();
  for (int i = 1; i < model.n_bodies; ++i) {
    mass += model.inertia[i].mass;
    sum += model.inertia[i].mass * data.oMi[i].act_point(model.inertia[i].com);
  }
  if (!(mass > 0.0)) {
    throw std::runtime_error("center_of_mass: the model's total mass is " + std::to_string(mass) +
                             " kg, must be > 0");
  }
  data.com = sum / mass;
  return data.com;
}

const Eigen::Matrix3Xd& center_of_mass_jacobian(const Model& model, Data& data) {
  center_of_mass(model, data);
  const double mass = model.total_mass();
  // Composite mass and first moment per subtree, then each joint column at once:
  // column (j, k) = sum over the subtree of j of m_i (v_O + w x p_i) / m with (v_O, w) the
  // world column of S_j e_k = (m_sub v_O + w x (m_sub c_sub)) / m.
  data.com_jacobian.setZero();
  for (int j = model.n_bodies - 1; j > 0; --j) {
    double m_sub = 0.0;
    Eigen::Vector3d first_moment = Eigen::Vector3d::Zero();
    for (int i = j; i < model.subtree_end[j]; ++i) {
      m_sub += model.inertia[i].mass;
      first_moment += model.inertia[i].mass * data.oMi[i].act_point(model.inertia[i].com);
    }
    const auto& s = model.motion_subspace[j];
    for (int k = 0; k < model.nv_joint[j]; ++k) {
      const Vector6d col = data.oMi[j].act_motion(Vector6d(s.col(k)));
      data.com_jacobian.col(model.idx_v[j] + k) =
          (m_sub * col.head<3>() + col.tail<3>().cross(first_moment)) / mass;
    }
  }
  return data.com_jacobian;
}

} // namespace plantar::multibody
