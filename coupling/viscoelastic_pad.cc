#include "coupling/viscoelastic_pad.h"

#include "fem/mesh_import.h"

#include <Eigen/LU>

#include <cmath>
#include <sstream>
#include <stdexcept>

namespace plantar::coupling {

ViscoelasticPad::ViscoelasticPad(const dealii::Triangulation<3>& triangulation, unsigned int degree,
                                 const fem::ViscoelasticMaterialTable& materials,
                                 const fem::ViscoelasticCondensationParameters& parameters,
                                 const Eigen::Matrix3d& rotation,
                                 const Eigen::Vector3d& translation)
    : materials_(materials) {
  triangulation_.copy_triangulation(triangulation);
  discretization_ = std::make_unique<fem::Discretization>(fem::cell_kind(triangulation_), degree);
  sole_ = std::make_unique<fem::ViscoelasticCondensation>(triangulation_, *discretization_,
                                                          materials_, parameters);
  const int n = static_cast<int>(sole_->n_contacts());
  positions_.resize(3, n);
  compliance_.resize(3 * n, 3 * n);
  offset_ = Eigen::VectorXd::Zero(3 * n);
  forces_.reinit(3 * n);
  displacements_.reinit(3 * n);
  set_placement(rotation, translation);
}

void ViscoelasticPad::set_placement(const Eigen::Matrix3d& rotation,
                                    const Eigen::Vector3d& translation) {
  if (!rotation.allFinite() ||
      (rotation.transpose() * rotation - Eigen::Matrix3d::Identity()).cwiseAbs().maxCoeff() >
          1e-12 ||
      rotation.determinant() < 0) {
    std::ostringstream msg;
    msg << "ViscoelasticPad: rotation R = [" << rotation << "] is not a rotation";
    throw std::invalid_argument(msg.str());
  }
  if (!translation.allFinite())
    throw std::invalid_argument("ViscoelasticPad: translation is not finite");
  rotation_ = rotation;
  const int n = n_contacts();
  for (int k = 0; k < n; ++k) {
    const auto& p = sole_->contact_positions()[k];
    positions_.col(k) = rotation * Eigen::Vector3d(p[0], p[1], p[2]) + translation;
  }
  const Eigen::Map<const Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>> c(
      sole_->effective_compliance().data(), 3 * n, 3 * n);
  for (int k = 0; k < n; ++k)
    for (int l = 0; l < n; ++l)
      compliance_.block<3, 3>(3 * k, 3 * l) =
          rotation * c.block<3, 3>(3 * k, 3 * l) * rotation.transpose();
  compliance_ = 0.5 * (compliance_ + compliance_.transpose()).eval();
  const dealii::Vector<double>& history = sole_->history_displacement();
  for (int k = 0; k < n; ++k)
    offset_.segment<3>(3 * k) =
        rotation * Eigen::Vector3d(history(3 * k), history(3 * k + 1), history(3 * k + 2));
}

ViscoelasticPad::~ViscoelasticPad() = default;

void ViscoelasticPad::finish_step(PadState& state) {
  const int n = n_contacts();
  if (state.n_nodes() != n)
    throw std::invalid_argument("ViscoelasticPad::finish_step: the state has " +
                                std::to_string(state.n_nodes()) + " nodes (expected " +
                                std::to_string(n) + ")");
  // F_pad = R^T a_k^T F_contact (a_k: node k's contact frame <- body, of this step).
  // U = C F + d from the contact solve (contact frames), without a damper's lag: the step's
  // displacement, so that the sole need not form C_eff F again.
  const Eigen::VectorXd& f = state.force();
  const Eigen::VectorXd& u = state.displacement();
  const bool solved = state.has_force() && state.damping() == 0.0;
  for (int k = 0; k < n; ++k) {
    const Eigen::Matrix3d to_pad = rotation_.transpose() * state.node_rotation(k).transpose();
    const Eigen::Vector3d force =
        state.has_force() ? Eigen::Vector3d(to_pad * f.segment<3>(3 * k)) : Eigen::Vector3d::Zero();
    const Eigen::Vector3d displacement =
        solved ? Eigen::Vector3d(to_pad * u.segment<3>(3 * k)) : Eigen::Vector3d::Zero();
    for (int d = 0; d < 3; ++d) {
      forces_(3 * k + d) = force[d];
      displacements_(3 * k + d) = displacement[d];
    }
  }
  sole_->advance(forces_, solved ? &displacements_ : nullptr);
  const dealii::Vector<double>& history = sole_->history_displacement();
  for (int k = 0; k < n; ++k)
    offset_.segment<3>(3 * k).noalias() =
        rotation_ * Eigen::Vector3d(history(3 * k), history(3 * k + 1), history(3 * k + 2));
  state.set_offset(offset_);
  state.set_lifted_offset(true);
}

} // namespace plantar::coupling
