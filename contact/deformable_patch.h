#pragma once
// The time stepper's view of a deformable patch: contact nodes whose displacements follow their
// forces (a pad condensed onto its contact nodes, coupling/pad_state.h). The stepper owns the
// geometry (the nodes fixed to a body) and the contact problem; the patch owns its compliance,
// its state across steps and its part of each step's problem. Per step the stepper calls:
//   deactivate()                       when no node can touch, else
//   activate() ... add_rate_terms()    when its block enters the problem, then after the solve
//   finish_step()                      always (the step's node impulses, the new state).
// Vectors are node-major, 3 per node, in the contact frames (n, t1, t2) of the nodes (on flat
// ground contact/ground_frame.h's, on a terrain each node's of contact/terrain.h) unless stated.

#include "contact/contact_problem.h"
#include "contact/contact_solver.h"
#include "contact/solver_settings.h"

#include <Eigen/Core>

namespace plantar::contact {

class DeformablePatch {
public:
  virtual ~DeformablePatch() = default;

  /// Number of contact nodes n.
  virtual int n_nodes() const = 0;
  /// Called once by the stepper that adds the patch: its block is problem.patches[index], the
  /// step dt (s) and theta of the Moreau-Jean theta method. Not in the time loop (allocates).
  virtual void attach(ContactProblem& problem, int index, double time_step, double theta) = 0;

  /// F at the end of the last step (3 n, N); zero when !has_force().
  virtual const Eigen::VectorXd& force() const = 0;
  virtual bool has_force() const = 0;
  /// U after the last step (3 n, m): the node displacements (normal first).
  virtual const Eigen::VectorXd& displacement() const = 0;
  /// The gap of node @p node (m) with the patch unloaded: @p gap - U_n + d_n (d the offset).
  virtual double unloaded_gap(int node, double gap) const = 0;

  /// No node can touch within the step: the block leaves the problem (set at @p first_contact
  /// with no contacts) and the massless patch relaxes.
  virtual void deactivate(int first_contact) = 0;
  /// The block enters the problem at contacts [first_contact, first_contact + n); @p rotation
  /// a = R_g^T R_body (contact frame <- body frame) of this step, R_g the flat ground's frame
  /// (contact/ground_frame.h). @p node_frames: nullptr when every node's contact frame is R_g
  /// (flat ground), else the n frames R_c,i of the nodes (world <- contact, contact/terrain.h),
  /// and node i's block rotation is a_i = R_c,i^T R_body = R_c,i^T R_g a. Writes the warm start
  /// of the nodes' impulses (n vectors, N s) to @p warm_start when it has one (else leaves
  /// them).
  virtual void activate(int first_contact, const Eigen::Matrix3d& rotation,
                        const Eigen::Matrix3d* node_frames, Eigen::Vector3d* warm_start) = 0;
  /// Adds the deformation-rate (and offset) terms of eq. 12 to the problem's free velocity of
  /// its rows; after the stepper has filled them.
  virtual void add_rate_terms() = 0;
  /// After the step: writes the step's node impulses (n vectors, N s: dt ((1-theta) F_prev +
  /// theta F)) to @p node_impulses and renews F and U; @p impulses the solution of the problem
  /// (all contacts) when the block was active, @p solver and @p result its solve.
  virtual void finish_step(const Eigen::Ref<const Eigen::VectorXd>& impulses,
                           const ContactSolver& solver, const SolverResult& result,
                           Eigen::Vector3d* node_impulses) = 0;
};

} // namespace plantar::contact
