#pragma once
// The velocity-level time stepper (David et al. 2008, eq. 4: explicit Adams order 1, i.e. a
// Moreau-Jean step) with linear-implicit joint springs, and frictional contact against the
// ground, a contact::Terrain (contact/terrain.h; the plane z = 0 by default), solved by
// contact/.
//
// One step of length dt, from (q, v) to (q+, v+), theta in [1/2, 1] (Moreau-Jean theta
// method; theta = 1 is the paper's eq. 4, the default):
//   K = diag(k_pd + k_passive), D = diag(d_pd + d_passive)       (1-DoF joints, 0 on the base)
//   spring forces at theta (q+ + ... weighted): f_s = K (q_ref,theta - q_theta) + D (v_ref -
//   v_theta) with v_theta = (1-theta) v + theta v+, q_theta = q + theta dt v_theta, q_ref,theta =
//   q_ref - (1-theta) dt v_ref (q_ref at the step's end, v_ref its rate) M_eff = M(q) + theta dt D
//   + theta^2 dt^2 K                    (linear-implicit) r     = M v + dt (tau - b(q, v) + K
//   (q_ref,theta - q - theta (1-theta) dt v)
//                     + D (v_ref - (1-theta) v)) + (1-theta) dt J_s^T F_s,prev
//   M_eff v_free = r,  M_eff = U U^T (U = L^T D^1/2: multibody/tree_factorization.h)
//   v+ = v_free + M_eff^-1 J^T p,   p the contact impulses (N s) of the contact problem
//   q+ = q (+) dt v_theta                                         (configuration.h)
// Nodes of a deformable patch (a condensed pad: contact::DeformablePatch, e.g. coupling::
// PadState, which holds its compliance and state) carry forces, not impacts: the impulse of a
// step is dt ((1-theta) F_prev + theta F), F = P / (theta dt) the force at the step's end and P
// the solver's unknown; the node's displacement at the end, U = C F (+ d), enters through the
// theta-weighted node velocity (x+ - x) / (theta dt), so the patch block is C / (theta dt)^2,
// the deformation-rate term -(U_prev - d) / (theta dt), the gap bias uses theta dt and the
// free velocity gets (1-theta)/theta times the node's velocity at v. Free points keep
// Moreau's impact law on v+. theta = 1/2 integrates linear springs (joints and pads) without
// numerical damping, second order; theta = 1 damps them (first order). The dofs of passive
// joints (compliant ankles) use passive_theta instead of theta, in K, D, v_theta and q+.
// With implicit_gains = false the springs are explicit instead (M_eff = M, forces at q, v):
// kept to show that stiff gains diverge that way.
//
// Contact problem (contact/contact_problem.h), rows in each contact's frame R_c = [n t1 t2] at
// its point (contact/terrain.h: the terrain's normal and tangents at the point's (x, y); on
// flat ground (n, t1, t2) = (z, x, y), contact/ground_frame.h, with the rows written out):
// J_c = R_c^T [I, -[r]x] J_b the point Jacobians, G = J_c U^-T (so G G^T = J_c M_eff^-1 J_c^T),
// v_free,c = J_c v_free, b = contact::normal_bias: restitution e v_n^- for a bouncing impact,
// gap/dt for a contact activated before touching (gap > 0, so that it lands on the plane
// instead of stopping above it, and no deeper), else the position correction.
// A point is active when its gap g (the terrain's first-order gap (p_z - h(p_x, p_y)) n_z; on
// flat ground z0 = 0 the point's z) satisfies g + dt min(v_free,n, 0) <= 0.
// A deformable patch (nodes fixed to a body) enters as a whole when any of its nodes is active
// (its unloaded gap, contact::DeformablePatch::unloaded_gap); its block is
// A C A^T / (theta dt)^2 with A = blockdiag(a_i), a_i = R_c,i^T R_body (node i's contact frame
// <- body frame; one a on flat ground), the block kept in the body frame
// (CompliantPatch::node_rotation), plus the deformation-rate term of eq. 12
// (compliance_terms.h); node gaps include the previous step's deformation.
// A step reads: free_motion (dynamics), select_candidates, assemble, the contact solve,
// apply_impulses, then each patch's finish_step and the integration of q.
// Cost: the rows of all candidates fixed to one body come from that body's 6 x nv Jacobian
// J_b and one sparse triangular solve U^-1 J_b^T per body and step (on the body's ancestors).
//
// After construction and the add_* calls, step() allocates nothing (tested with Eigen's
// malloc guard, except inside Eigen's blocked Cholesky of a patch block larger than about
// 100 contacts, see contact_solver.h).

#include "contact/contact_problem.h"
#include "contact/contact_solver.h"
#include "contact/deformable_patch.h"
#include "contact/position_correction.h"
#include "contact/solver_settings.h"
#include "contact/terrain.h"
#include "multibody/data.h"
#include "multibody/model.h"
#include "multibody/pd_gains.h"
#include "multibody/tree_factorization.h"

#include <Eigen/Cholesky>
#include <Eigen/Core>
#include <chrono>
#include <vector>

namespace plantar::multibody {

struct StepperParameters {
  double time_step = 1e-3; ///< dt, s, (0, 0.1]; the paper's walk uses 1 to 5 ms
  int max_contacts = 64;   ///< size of the contact problem, [0, 100000]
  /// Linear-implicit joint PD and passive springs (default). False: explicit (comparison only).
  bool implicit_gains = true;
  /// Factor M_eff along the kinematic tree (default, multibody/tree_factorization.h). False:
  /// Eigen's dense Cholesky M_eff = L L^T (the same step up to round-off; comparison only).
  bool tree_factorization = true;
  /// Evaluate the bias forces C(q, v) v + G(q) at v_mid = (v + v_free) / 2 (one more RNEA
  /// and triangular solve) instead of at v as in eq. 4. Second order in the gyroscopic and
  /// transport terms: removes most of the first-order energy drift of fast free rotations.
  bool midpoint_bias = false;
  /// theta of the Moreau-Jean theta method, [0.5, 1]: weight of the step's end in the joint
  /// springs, the sole forces and the position update (1: eq. 4, first order, damps the stiff
  /// springs; 0.5: second order, no numerical damping of linear springs).
  double theta = 1.0;
  /// theta of the passive joints (Model::passive_stiffness or passive_damping > 0, e.g. the
  /// compliant ankle's springs), [0.5, 1], in place of theta for those degrees of freedom. A
  /// light foot on a stiff damped spring has a fast overdamped mode (c dt / I >> 1) that theta
  /// = 1/2 maps to nearly -1 per step (it rings at the step's frequency, under the contacts
  /// too); 1 (backward Euler) damps it. A deformable patch below such a joint needs
  /// passive_theta == theta (its node velocity follows one theta).
  double passive_theta = 1.0;
  contact::NormalBiasParameters normal_bias; ///< restitution e, position correction
  contact::SolverSettings solver;            ///< contact solver (ADMM by default)
  /// Throw std::runtime_error when the contact solver does not converge (default: only count
  /// it in StepReport; non-finite results always throw).
  bool throw_if_not_converged = false;
  /// m, >= 0 (infinity allowed): a candidate point (or a patch, by any node) enters the
  /// contact problem when g + dt min(v_free,n, 0) <= contact_margin, g the gap (for a patch
  /// node the unloaded one, g - U_prev + d). 0: only what can touch within the step;
  /// infinity: every candidate (the full problem, for tests).
  double contact_margin = 0.0;
  /// Throws std::invalid_argument naming the field, value and range.
  void validate() const;
};

/// Wall seconds (steady_clock) spent in the phases of Stepper::step since the last reset.
struct StepProfile {
  double dynamics = 0;      ///< CRBA, RNEA, factorization of M_eff, v_free, v+, integration
  double contact_build = 0; ///< candidate Jacobians and gaps, G = J U^-T, v_free,c, bias
  double sole_update = 0;   ///< patch blocks A C A^T / dt^2, deformation-rate term, U_c
  double contact_solve = 0; ///< contact::ContactSolver::solve
  long n_steps = 0;
  long n_solves = 0;     ///< steps with at least one active contact
  long n_solve_rows = 0; ///< sum over solves of 3 n_contacts
  double total() const { return dynamics + contact_build + sole_update + contact_solve; }
};

/// What happened in one step.
struct StepReport {
  int n_contacts = 0; ///< active contacts (patch nodes included)
  contact::SolverResult solver;
};

class Stepper {
public:
  /// @p model and @p terrain must outlive the stepper (the default: the plane z = 0,
  /// contact::flat_ground()).
  Stepper(const Model& model, const StepperParameters& parameters, const contact::Terrain& terrain);
  Stepper(const Model& model, const StepperParameters& parameters);

  void set_gains(const PdGains& gains);
  const PdGains& gains() const { return gains_; }
  const StepperParameters& parameters() const { return parameters_; }

  /// A candidate contact point fixed to @p body, @p position in body coordinates (m), friction
  /// coefficient mu >= 0. Returns its index. Not in the time loop (allocates).
  int add_contact_point(int body, const Eigen::Vector3d& position, double friction);

  /// A deformable patch: @p nodes (3 x n, body coordinates, m) fixed to @p body, friction mu,
  /// whose compliance and state are @p patch (e.g. coupling::PadState; not owned, must outlive
  /// the stepper; n = patch.n_nodes()). Returns its index. Not in the time loop (allocates).
  int add_deformable_patch(int body, const Eigen::Matrix3Xd& nodes, double friction,
                           contact::DeformablePatch& patch);

  /// Advances (q, v) by one step in place. @param q size nq, @param v size nv,
  /// @param tau feed-forward joint forces (nv; base entries are external base wrenches in the
  /// base frame), @param q_ref (nq) and @param v_ref (nv) the PD references.
  /// Throws std::runtime_error on a non-positive-definite M_eff or a non-finite result.
  StepReport step(Eigen::Ref<Eigen::VectorXd> q, Eigen::Ref<Eigen::VectorXd> v,
                  const Eigen::Ref<const Eigen::VectorXd>& tau,
                  const Eigen::Ref<const Eigen::VectorXd>& q_ref,
                  const Eigen::Ref<const Eigen::VectorXd>& v_ref);

  /// Data of the last step's start configuration (M, bias, placements).
  const Data& data() const { return data_; }
  const contact::ContactProblem& problem() const { return problem_; }
  /// The impulses (N s, 3 problem().n_contacts, contact frames) the last contact solve started
  /// from: each active point's impulse of the step before (zero where it was not in contact),
  /// before the solver's projection onto the cones. With problem() it replays that solve.
  Eigen::Ref<const Eigen::VectorXd> warm_start() const {
    return warm_start_.head(3 * problem_.n_contacts);
  }
  /// Impulse (N s, the point's contact frame (n, t1, t2): point_frame(); on flat ground
  /// [n = z, t1 = x, t2 = y]) of the last step on contact point @p point (index returned by
  /// add_contact_point).
  const Eigen::Vector3d& point_impulse(int point) const {
    return point_impulse_[n_patch_points_ + point];
  }
  /// Same for node @p node of patch @p patch: the step's whole impulse,
  /// dt ((1-theta) F_prev + theta F) (theta = 1: the solver's impulse).
  const Eigen::Vector3d& node_impulse(int patch, int node) const {
    return point_impulse_[patches_[patch].first_point + node];
  }
  /// R_c (world <- contact frame) of contact point @p point at the last step (its terrain frame;
  /// the flat ground's before the first step).
  const Eigen::Matrix3d& point_frame(int point) const { return frame_[n_patch_points_ + point]; }
  /// Same for node @p node of patch @p patch.
  const Eigen::Matrix3d& node_frame(int patch, int node) const {
    return frame_[patches_[patch].first_point + node];
  }
  const contact::Terrain& terrain() const { return *terrain_; }
  /// Sum of the last step's contact forces on the robot (N, world): impulses / dt.
  Eigen::Vector3d total_contact_force() const;
  double time_step() const { return parameters_.time_step; }
  /// Accumulated phase timings (a few clock reads per step, no allocation).
  const StepProfile& profile() const { return profile_; }
  void reset_profile() { profile_ = StepProfile{}; }

private:
  struct ContactPoint {
    int body;
    Eigen::Vector3d position;
    double friction;
  };
  struct Patch { // the geometry; the state is the DeformablePatch's
    int body;
    Eigen::Matrix3Xd nodes;
    int first_point; // index of its first node in points_
    contact::DeformablePatch* state;
  };

  void resize_workspaces();
  int add_body_slot(int body);
  /// Factors M_eff = U U^T; false if it is not positive definite.
  bool factor_effective_mass();
  /// x <- M_eff^-1 x, x <- U^-1 x and x <- U^-T x (@p x nv x k).
  void solve_effective_mass(Eigen::VectorXd& x) const;
  void half_solve(Eigen::Ref<Eigen::MatrixXd> x) const;
  void half_solve_transpose(Eigen::Ref<Eigen::MatrixXd> x) const;
  /// Gap, frame, lever r = p - o_b and normal velocities (at v and v_free) of candidate
  /// @p point; returns the normal free velocity.
  double evaluate_candidate(int point, double extra_gap);
  /// Row block k (3 rows) of G and v_free,c for candidate @p point.
  void fill_contact_rows(int k, int point);
  /// Rigid factor with 6 columns per contact body: G_k = S_k Z_b, Z Z^T = H H^T, H the
  /// stacked J_b U^-T of the bodies in contact (semi-definite Cholesky).
  void reduce_rigid_factor();
  /// The phases of step().
  void free_motion(const Eigen::Ref<const Eigen::VectorXd>& q,
                   const Eigen::Ref<const Eigen::VectorXd>& v,
                   const Eigen::Ref<const Eigen::VectorXd>& tau,
                   const Eigen::Ref<const Eigen::VectorXd>& q_ref,
                   const Eigen::Ref<const Eigen::VectorXd>& v_ref);
  /// The active candidates into active_points_ (patches first); returns their number.
  int select_candidates();
  /// G, v_free,c, b, mu and the warm start of the n active contacts.
  void assemble(int n, const Eigen::Ref<const Eigen::VectorXd>& v);
  /// v+ = v_free + M_eff^-1 J^T p; v_mid_ = v_theta (per dof: dof_theta_).
  void apply_impulses(int n, Eigen::Ref<Eigen::VectorXd> v);
  /// Adds the wall time since the last lap to @p bucket (profile_).
  void lap(double& bucket);
  /// R_c^T (v_o + w x r) for candidate @p point and the body twist @p twist (v_o, w), world.
  Eigen::Vector3d contact_velocity(int point, const Vector6d& twist) const;
  /// A contact-frame vector @p c of candidate @p point in world components: R_c c.
  Eigen::Vector3d to_world(int point, const Eigen::Vector3d& c) const;

  const Model& model_;
  StepperParameters parameters_;
  const contact::Terrain* terrain_;
  bool level_ground_; // the terrain is z = level_: the frame is ground_frame.h's everywhere
  double level_ = 0.0;
  Data data_;
  PdGains gains_;
  std::vector<ContactPoint> points_; // patch nodes first, then free points
  std::vector<Patch> patches_;
  std::vector<Eigen::Vector3d> point_impulse_;
  int n_patch_points_ = 0;

  // Workspaces (sized once).
  Eigen::MatrixXd effective_mass_;  // M_eff
  TreeFactorization factorization_; // M_eff = L^T D L = U U^T
  Eigen::MatrixXd dense_factor_;    // tree_factorization = false: U = L, M_eff = L L^T
  Eigen::VectorXd rhs_, v_free_, dv_, bias_start_, v_mid_;
  Eigen::VectorXd dof_theta_; // nv: theta, or passive_theta for a passive joint's dofs
  // Per body carrying candidates ("slot"): the contact rows of its points are S(r) J_b with
  // J_b its 6 x nv Jacobian (body_origin_jacobian) and S(r) = R_c^T [I, -[r]x] (3 x 6).
  std::vector<int> body_slot_;                                          // per body, -1: none
  std::vector<int> slot_body_;                                          // per slot
  std::vector<Eigen::Matrix<double, 6, Eigen::Dynamic>> slot_jacobian_; // J_b
  std::vector<Eigen::MatrixXd> slot_factor_;                            // U^-1 J_b^T, nv x 6
  std::vector<Eigen::Matrix<double, 6, Eigen::Dynamic>> slot_factor_t_; // J_b U^-T
  std::vector<Vector6d> slot_velocity_, slot_free_velocity_, slot_impulse_;
  std::vector<char> slot_factored_; // slot_factor_ computed this step
  // Per slot: its body's ancestor dofs, ascending (where J_b^T and U^-1 J_b^T are nonzero).
  std::vector<std::vector<int>> slot_dofs_;
  // Reduced rigid factor (when 6 x slots < nv): Z Z^T = H H^T over the slots in contact.
  bool reduce_rigid_ = false;
  Eigen::MatrixXd reduced_gram_;   // 6 S x 6 S, H H^T then Z (lower)
  std::vector<int> reduced_slots_; // slots in contact this step (capacity S)
  std::vector<Eigen::Matrix<double, 6, Eigen::Dynamic>> slot_reduced_; // rows of Z, 6 x 6 S
  Eigen::VectorXd impulses_;                                           // 3 max
  Eigen::VectorXd warm_start_;         // 3 max, impulses_ before the solve
  Eigen::VectorXd gap_, v_before_;     // per candidate point
  std::vector<Eigen::Vector3d> lever_; // per candidate point: r = p - o_b (world, m)
  std::vector<Eigen::Matrix3d> frame_; // per candidate point: R_c of its last evaluation
  std::vector<int> active_points_;     // capacity = number of points
  contact::ContactProblem problem_;
  contact::ContactSolver solver_;
  StepProfile profile_;
  std::chrono::steady_clock::time_point lap_start_;
};

} // namespace plantar::multibody
