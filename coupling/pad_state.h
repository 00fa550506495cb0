#pragma once
// The state of a deformable pad (a sole, a knee pad) in the time loop: its compliance C on its
// contact nodes (body frame), the node forces and displacements across steps, the parking of its
// block while it is lifted, its Kelvin-Voigt damping, its affine offset, and the warm start
// kept for the contact solver. It implements the stepper's contact::DeformablePatch.
//
// With the stepper's step dt and theta (multibody/stepper.h):
//   F = P / (theta dt) the node forces at the step's end (P the solver's unknown),
//   U = C F (+ d) their displacements (d an offset, set_compliance: an affine pad model),
//   the block C / (theta dt)^2 and the deformation-rate term -(U_prev - d) / (theta dt),
// and with damping beta (set_damping) U + beta dU/dt = C F:
//   U+ = a C F + U_bar,  a = theta / (beta/dt + theta),
//   U_bar = ((beta/dt - (1-theta)) U + (1-theta) C F_prev) / (beta/dt + theta),
// so the block becomes a C / (theta dt)^2 and the deformation-rate term -(U - U_bar)/(theta dt).
// A lifted pad relaxes at once (massless, beta << the swing), or keeps U = d when its offset is
// its free recovery (set_lifted_offset).
// A node's impulse over the step is dt ((1-theta) F_prev + theta F).

#include "contact/deformable_patch.h"

#include <Eigen/Core>

namespace plantar::coupling {

class PadState final : public contact::DeformablePatch {
public:
  /// @p compliance C (3 n x 3 n, m/N, body frame, node-major [x y z] blocks, symmetric
  /// positive semi-definite, finite). Throws std::invalid_argument naming the size or the
  /// asymmetry.
  explicit PadState(const Eigen::Ref<const Eigen::MatrixXd>& compliance);

  /// Replaces C by @p compliance (same size, symmetric, finite, body frame) and sets the
  /// offset d to @p offset (3 n, m, body frame): U = C F + d, an affine (e.g. tangent,
  /// coupling/nonlinear_condensed_sole.h) pad model. Between steps; does not allocate. Throws
  /// std::invalid_argument on a size, asymmetry or non-finite value, or an offset on a
  /// damped pad.
  void set_compliance(const Eigen::Ref<const Eigen::MatrixXd>& compliance,
                      const Eigen::Ref<const Eigen::VectorXd>& offset);
  /// Sets the offset d alone (3 n, m, body frame), keeping C: U = C F + d, e.g. the history
  /// displacement of a viscoelastic pad (coupling/viscoelastic_pad.h), renewed every step.
  /// Between steps; O(n), does not allocate. Throws std::invalid_argument on a size or a
  /// non-finite value, or on a damped pad.
  void set_offset(const Eigen::Ref<const Eigen::VectorXd>& offset);
  /// With @p on, a lifted pad keeps U = d, its unloaded shape (an offset pad whose offset is
  /// its free recovery, e.g. a viscoelastic pad: coupling/viscoelastic_pad.h), renewed at every
  /// lifted step, instead of relaxing at once to U = 0 (the default). Between steps.
  void set_lifted_offset(bool on) { lifted_offset_ = on; }
  /// a = R_g^T R_body of the last activate() (contact frame <- body frame, R_g the flat
  /// ground's frame): the frame of force() and displacement() on flat ground (node_force(k) =
  /// a F_body(k)). On a terrain each node has its own: node_rotation().
  const Eigen::Matrix3d& rotation() const { return rotation_; }
  /// a_k = R_c,k^T R_body of node @p node at the last activate() (rotation() on flat ground).
  Eigen::Matrix3d node_rotation(int node) const {
    return per_node_ ? Eigen::Matrix3d(node_rotations_.middleCols<3>(3 * node)) : rotation_;
  }
  /// R_c,k c: a vector @p c of node @p node's contact frame (force(), displacement()) in world
  /// components.
  Eigen::Vector3d node_to_world(int node, const Eigen::Vector3d& c) const;
  /// Kelvin-Voigt damping time beta (s, >= 0, finite) of a stiffness-proportional pad damping
  /// D = beta K, which the static condensation keeps exactly; loss factor beta omega. Between
  /// steps; does not allocate. Throws std::invalid_argument on beta or on a pad with an offset.
  void set_damping(double beta);
  double damping() const { return damping_; }
  /// C (3 n x 3 n, m/N, body frame).
  const Eigen::MatrixXd& compliance() const { return compliance_; }
  /// F of node @p node at the end of the last step (N, contact frame (n, t1, t2)).
  Eigen::Vector3d node_force(int node) const { return force_.segment<3>(3 * node); }

  // contact::DeformablePatch.
  int n_nodes() const override { return static_cast<int>(compliance_.rows() / 3); }
  void attach(contact::ContactProblem& problem, int index, double time_step, double theta) override;
  const Eigen::VectorXd& force() const override { return force_; }
  bool has_force() const override { return has_force_; }
  const Eigen::VectorXd& displacement() const override { return displacement_; }
  double unloaded_gap(int node, double gap) const override {
    return gap - displacement_[3 * node] + (has_offset_ ? offset_contact_[3 * node] : 0.0);
  }
  void deactivate(int first_contact) override;
  void activate(int first_contact, const Eigen::Matrix3d& rotation,
                const Eigen::Matrix3d* node_frames, Eigen::Vector3d* warm_start) override;
  void add_rate_terms() override;
  void finish_step(const Eigen::Ref<const Eigen::VectorXd>& impulses,
                   const contact::ContactSolver& solver, const contact::SolverResult& result,
                   Eigen::Vector3d* node_impulses) override;

private:
  contact::CompliantPatch& block() { return problem_->patches[index_]; }
  /// a C / (theta dt)^2 into the held block (the problem's while active, else parked_).
  void set_block();

  Eigen::MatrixXd compliance_; // C, body frame
  contact::ContactProblem* problem_ = nullptr;
  int index_ = -1;
  double time_step_ = 0, theta_ = 1;
  Eigen::VectorXd displacement_;   // U of the last step, contact frames
  Eigen::MatrixXd parked_;         // the block C/(theta dt)^2 while inactive
  Eigen::VectorXd offset_;         // d (body frame)
  Eigen::VectorXd offset_contact_; // d in the contact frames of the current step
  bool has_offset_ = false;
  bool lifted_offset_ = false; // lifted: U = d (set_lifted_offset) rather than 0
  Eigen::Matrix3d rotation_ = Eigen::Matrix3d::Identity(); // a of the current step
  bool per_node_ = false;           // the last activate() had node frames (a terrain)
  Eigen::Matrix3Xd node_rotations_; // a_k of the current step (3 x 3 n), per_node_
  Eigen::Matrix3Xd frames_;         // R_c,k of the current step (3 x 3 n), per_node_
  Eigen::VectorXd product_;         // C/(theta dt)^2 (I (x) a)^T p of the last solve (body frame)
  Eigen::VectorXd impulse_;         // (I (x) a)^T p of the last solve (body frame), N s
  bool has_last_solve_ = false;     // product_ and impulse_ hold the last step's solve
  int sweeps_since_fresh_ = 0;      // solver sweeps since product_ was last computed afresh
  Eigen::VectorXd force_;           // F at the end of the last step (contact frames), N
  bool has_force_ = false;          // force_ is not zero
  double damping_ = 0;              // beta (s)
  Eigen::VectorXd elastic_;         // C F of the last step (contact frames), beta > 0
  Eigen::VectorXd relaxation_;      // U - U_bar of this step (contact frames), beta > 0
};

} // namespace plantar::coupling
