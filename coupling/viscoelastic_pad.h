#pragma once
// A viscoelastic (Prony) pad or sole in the time loop: a fem::ViscoelasticCondensation placed on
// a body, driving a PadState as an affine pad U = C_eff F + d with the history displacement d
// renewed every step (issue 24).
//
// Per step of the stepper (dt fixed, equal to the sole's):
//   stepper.step(...)        the contact solve with C_eff and the offset d^n: U^{n+1} = C_eff
//                            F^{n+1} + d^n (exact: fem/viscoelastic_condensation.h);
//   pad.finish_step(state)   F^{n+1} from the state (contact frames -> body -> pad frame),
//                            advance() of the FEM state, d^{n+1} (pad -> body frame) set on the
//                            state by PadState::set_offset.
// Frames: pad (mesh) frame -> body frame by x_body = R x_pad + t; C_body = blockwise R C R^T.
// A lifted pad (no force) keeps relaxing: advance() with F = 0, and its state shows U = d, the
// free recovery (PadState::set_lifted_offset, set by finish_step), so that it re-enters contact
// with its recovering shape.

#include "coupling/pad_state.h"
#include "fem/viscoelastic_condensation.h"

#include <deal.II/grid/tria.h>
#include <deal.II/lac/vector.h>

#include <Eigen/Core>

#include <memory>

namespace plantar::coupling {

class ViscoelasticPad {
public:
  /// Builds the condensed viscoelastic pad on a copy of @p triangulation with Lagrange degree
  /// @p degree (1 or 2, P or Q by the mesh), the materials @p materials (copied) and
  /// @p parameters (time_step = the stepper's dt), placed on its body by @p rotation R
  /// (orthonormal, pad -> body) and @p translation t (m). Throws std::invalid_argument on bad
  /// input (fem::ViscoelasticCondensation's, or R not a rotation).
  ViscoelasticPad(const dealii::Triangulation<3>& triangulation, unsigned int degree,
                  const fem::ViscoelasticMaterialTable& materials,
                  const fem::ViscoelasticCondensationParameters& parameters,
                  const Eigen::Matrix3d& rotation, const Eigen::Vector3d& translation);
  ~ViscoelasticPad();
  ViscoelasticPad(const ViscoelasticPad&) = delete; // the sole references the members
  ViscoelasticPad& operator=(const ViscoelasticPad&) = delete;

  int n_contacts() const { return static_cast<int>(positions_.cols()); }
  /// Contact node positions in the body frame (3 x n, m).
  const Eigen::Matrix3Xd& contact_positions() const { return positions_; }
  /// C_eff in the body frame (3 n x 3 n, m/N, node-major): PadState's compliance.
  const Eigen::MatrixXd& compliance() const { return compliance_; }
  /// The history displacement d in the body frame (3 n, m): PadState's offset.
  const Eigen::VectorXd& offset() const { return offset_; }
  const fem::ViscoelasticCondensation& sole() const { return *sole_; }
  const fem::Discretization& discretization() const { return *discretization_; }

  /// Places the pad anew on its body (R orthonormal, pad -> body; t in m): contact_positions()
  /// and compliance() follow. Before the state is made from compliance() (set-up only,
  /// allocates nothing new). Throws std::invalid_argument if R is not a rotation.
  void set_placement(const Eigen::Matrix3d& rotation, const Eigen::Vector3d& translation);

  /// After each step of the stepper that holds @p state (made from compliance()): advances the
  /// FEM state under the step's node forces and sets the next offset on @p state (and marks it
  /// to keep U = d while lifted: PadState::set_lifted_offset). Does not allocate.
  void finish_step(PadState& state);

private:
  dealii::Triangulation<3> triangulation_;
  std::unique_ptr<fem::Discretization> discretization_;
  fem::ViscoelasticMaterialTable materials_;
  std::unique_ptr<fem::ViscoelasticCondensation> sole_;
  Eigen::Matrix3d rotation_;
  Eigen::Matrix3Xd positions_;
  Eigen::MatrixXd compliance_;
  Eigen::VectorXd offset_;
  dealii::Vector<double> forces_;        // pad frame, N
  dealii::Vector<double> displacements_; // pad frame, m: the solve's U = C F + d
};

} // namespace plantar::coupling
