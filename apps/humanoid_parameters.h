#pragma once
// Scene parameters of the humanoid scenes (stand, drop, lean, walk): one struct per .prm
// subsection (Robot, Contact, Control, Walking, Lean, Simulation), each with declare() (name,
// default, range, help) and parse(). The defaults are the paper's HRP-2 set-up (David et al.
// 2008) and the public HRP-2 figures of shared/reference/hrp2.md.

#include "apps/foot_model_registry.h"
#include "contact/solver_settings.h"
#include "coupling/reduced_sole.h"
#include "fem/sole_parameters.h"
#include "multibody/walking/balance_controller.h"
#include "multibody/walking/footstep_plan.h"
#include "multibody/walking/humanoid.h"
#include "multibody/walking/leg_solver.h"
#include "multibody/walking/terrain_footsteps.h"

#include <deal.II/base/parameter_handler.h>

#include <array>
#include <filesystem>
#include <string>
#include <vector>

namespace plantar::app {

/// Subsection "Robot".
struct RobotParameters {
  std::filesystem::path urdf_file; ///< resolved like Sole paths; humanoid scenes need one
  FootForm foot_form = FootForm::rigid;
  /// `plantar run`: run every form of this list (Foot form ignored) into DIR/<form>/; empty:
  /// Foot form only. `plantar sweep`: the forms of the sweep.
  std::vector<FootForm> foot_forms;
  /// Rigid feet and compliant ankles: 0, the 8 points of the sole outline; n in [2, 15], an
  /// n x n grid over Sole/Length x Sole/Width (the outline's corners included).
  int rigid_foot_grid = 0;
  /// Rigid feet and compliant ankles on uneven ground: the deepest point of the sole's face in
  /// the ground (an 11 x 11 grid over it, m) warns past rigid_sole_depth_warning and stops the
  /// run past rigid_sole_max_depth (apps/validity_monitor.h), both (0, 1] m.
  double rigid_sole_depth_warning = 0.001;
  double rigid_sole_max_depth = 0.005;
  double ankle_linear_stiffness = 40000;      ///< N/m, > 0 (hrp2.md, public HRP-2 flexibility)
  double ankle_linear_damping = 600;          ///< N s/m, >= 0
  double ankle_angular_stiffness = 600;       ///< N m/rad, > 0
  double ankle_angular_damping = 60;          ///< N m s/rad, >= 0
  bool ankle_deflection_compensation = false; ///< feed-forward of the static spring deflection
  double com_height = 0.814; ///< m, (0.1, 3): CoM height of the standing/walking posture
  /// Base link, legs, soles, controlled joints, posture: the names of the scene.
  walking::HumanoidDescription humanoid;
  walking::LegIkMethod leg_ik = walking::LegIkMethod::automatic;
  /// compliant ankle: spring centre in the foot link frame, m.
  Eigen::Vector3d ankle_compliance_centre = Eigen::Vector3d::Zero();
  static void declare(dealii::ParameterHandler& prm);
  void parse(dealii::ParameterHandler& prm, const std::filesystem::path& scene_directory);
};

/// Sole/Model (declared by fem::SoleParameters): how the FEM sole deforms.
enum class SoleModel {
  linear,       ///< condensed once (coupling/condensed_sole.h)
  hyperelastic, ///< tangent re-condensed in the time loop (coupling/nonlinear_condensed_sole.h)
};
/// The SoleModel of @p sole's Sole/Model (parsed by fem::SoleParameters, which keeps it as
/// text: the one place that reads it).
SoleModel sole_model(const fem::SoleParameters& sole);

/// Entries of subsection "Sole" read by the humanoid scenes only: the reduced sole
/// (coupling/reduced_sole.h) for Robot/Foot form = fem sole.
struct SoleReductionParameters {
  int patches_x = 0; ///< 0: the full condensed sole; else nx x ny grid of contact patches
  int patches_y = 0; ///< >= 1 when patches_x >= 1
  /// Reduced patches = auto: the coarsest g x g grid whose reduction error estimate
  /// (coupling::choose_reduction) is at most `tolerance`.
  bool automatic = false;
  double tolerance = 0.01; ///< Sole/Reduction tolerance, (0, 1)
  /// Sole/Reduction spacing: the grid's cells equal or graded towards the sole's edges (the
  /// default: on the 5 mm to 2.5 mm soles its estimate is 2 to 8 times smaller than the uniform
  /// grid's from 8 x 8 on; docs/performance.md).
  coupling::GridSpacing spacing = coupling::GridSpacing::chebyshev;
  /// Sole/Reduction weights: a patch force shared by the nodes' areas (a uniform patch
  /// pressure, coupling::pressure_weights) or equally.
  bool area_weights = true;
  /// Sole/Reduction basis: one patch per grid cell (a cell-wise constant pressure) or per grid
  /// vertex (a continuous, cell-wise bilinear pressure; coupling/reduced_sole.h). Bilinear, the
  /// default, needs 2.5 to 6 times fewer contacts for a given estimate (docs/performance.md).
  coupling::PatchBasis basis = coupling::PatchBasis::bilinear;
  /// Sole/Reduction quantity: what Sole/Reduction tolerance bounds (coupling/reduced_sole.h).
  coupling::ReductionQuantity quantity = coupling::ReductionQuantity::stiffness;
  bool reduced() const { return patches_x > 0 || automatic; }
  static void declare(dealii::ParameterHandler& prm);
  void parse(dealii::ParameterHandler& prm);
};

/// The scene-file name of @p quantity (Sole/Reduction quantity).
const char* reduction_quantity_name(coupling::ReductionQuantity quantity);

/// Entries of subsection "Sole" read by the humanoid scenes only: the validity limits of the
/// FEM sole (apps/validity_monitor.h, docs/reliability.md). Compressions and strains are
/// fractions of Sole/Thickness t, per contact node k after every step:
///   compression c_k = u_k . n / t  (u_k: the node's displacement, n: the sole's normal into
///                                   the foot),
///   strain      e_k = |u_k| / t    (the displacement gradient through the thickness, averaged
///                                   over the node's column; normal strain or shear angle).
/// The hyperelastic sole is watched through J = det F (min over its quadrature points).
struct SoleValidityParameters {
  double compression_warning = 0.1; ///< linear sole: warn past max_k c_k, (0, 1]
  double max_compression = 0.5;     ///< linear sole: fail past max_k c_k, (0, 1]
  double strain_warning = 0.1;      ///< linear sole: warn past max_k e_k, > 0
  double max_strain = 1.0;          ///< linear sole: fail past max_k e_k, > 0
  double jacobian_warning = 0.5;    ///< hyperelastic sole: warn below min J, (0, 1)
  double min_jacobian = 0.1;        ///< hyperelastic sole: fail below min J, (0, 1)
  static void declare(dealii::ParameterHandler& prm);
  void parse(dealii::ParameterHandler& prm);
};

/// Subsection "Contact".
struct ContactParameters {
  double friction = 0.8;            ///< Coulomb mu, [0, 10]
  double restitution = 0.0;         ///< Newton e, [0, 1]
  double position_correction = 0.2; ///< fraction of a penetration removed per step, (0, 1]
  contact::ContactSolverType solver =
      contact::ContactSolverType::automatic; ///< docs/contact_solvers.md
  double tolerance = 1e-8;                   ///< m/s, natural-map residual, > 0
  int max_iterations = 500;                  ///< >= 1
  bool sticking_direct = true;               ///< direct solve when every contact sticks
  double sweep_skip = 0.0; ///< Gauss-Seidel: skip contacts within this x tolerance
  /// auto: Newton attempts stop after this many iterations without halving the residual.
  int newton_stall_iterations = contact::SolverSettings().auto_newton_stall_iterations;
  /// Failure residual's default: this many tolerances (docs/reliability.md: why 10).
  static constexpr double default_failure_factor = 10;
  /// m/s: an unconverged solve above this stops the run; the scene gives a residual or
  /// 'k x Tolerance' (k >= 1; default default_failure_factor).
  double failure_residual = default_failure_factor * tolerance;
  static void declare(dealii::ParameterHandler& prm);
  void parse(dealii::ParameterHandler& prm);
};

/// Control/Stabilizer.
enum class StabilizerType {
  none, ///< PD playback of the reference (the paper's)
  dcm,  ///< sensors -> estimator -> DCM stabilizer -> joint references (docs/stabilizer.md)
};

/// Subsection "Control": PD tracking of the joint reference, same gains on every actuated
/// joint: tau = kp (q_ref - q) + kd (v_ref - v); optionally a balance stabilizer that only
/// changes q_ref (multibody/walking/balance_controller.h), with its sensors and estimator.
struct ControlParameters {
  double stiffness = 1e4; ///< kp, N m/rad, >= 0
  double damping = 200;   ///< kd, N m s/rad, >= 0
  StabilizerType stabilizer = StabilizerType::none;
  /// Gains, filters, estimator and sensor noise (frame indices are set by the simulation
  /// from the names below).
  walking::BalanceParameters balance;
  double cop_margin = 0.01; ///< m: CoP targets this far inside the sole outline
  /// 1/s: > 0 sets the foot damping per axis from the foot's tilt stiffness, D = k / rate with
  /// 1/k = 1/kp + 1/k_foot (FootModel::tilt_stiffness); 0: Foot damping on both axes.
  double foot_damping_rate = 0;
  std::string imu_frame;                     ///< empty: Robot/Base link
  std::array<std::string, 2> force_frames{}; ///< right, left; empty: the foot links
  static void declare(dealii::ParameterHandler& prm);
  void parse(dealii::ParameterHandler& prm);
};

/// Subsection "Walking": footsteps, timing and step height (walking::WalkingParameters) and
/// the preview horizon.
/// Walking/Footstep placement.
enum class FootstepPlacement {
  flat,    ///< every sole at z = 0, level (the walk is raised onto the ground under the feet)
  terrain, ///< each sole at rest on the terrain under it (multibody/walking/terrain_footsteps.h)
};

struct WalkingSceneParameters {
  walking::WalkingParameters walk;
  double preview_time = 1.6; ///< s, Kajita 2003
  FootstepPlacement placement = FootstepPlacement::flat;
  /// A foot of more than footprint_samples^2 contact points is placed by a grid of
  /// footprint_samples per side over its outline, [2, 100].
  int footprint_samples = 9;
  /// Footstep placement = terrain: the ZMP target of each placement is the point of its support
  /// polygon shrunk by this margin nearest to the sole centre (m, >= 0).
  double zmp_margin = 0.03;
  /// Footstep placement = terrain: each footstep may move by up to foothold.radius (m) to where
  /// its support holds the sole centre (terrain_footsteps.h place_on_foothold); 0: it stays.
  walking::FootholdSearch foothold;
  static void declare(dealii::ParameterHandler& prm);
  void parse(dealii::ParameterHandler& prm);
};

/// Subsection "Lean" (the paper's inclination test).
struct LeanSceneParameters {
  double final_angle_deg = 14.3; ///< deg, |.| <= 20
  double start_time = 0.5;       ///< s, >= 0
  double ramp_time = 3.0;        ///< s, > 0
  double hold_time = 2.0;        ///< s, >= 0
  static void declare(dealii::ParameterHandler& prm);
  void parse(dealii::ParameterHandler& prm);
};

/// Subsection "Simulation".
struct SimulationParameters {
  /// A push on the waist (base origin): force (magnitude / duration) along the unit
  /// direction, world axes, during [push_time, push_time + push_duration).
  double push_time = 1.0;                                    ///< s, >= 0
  Eigen::Vector3d push_direction = Eigen::Vector3d::UnitX(); ///< normalised when parsed
  double push_magnitude = 0;                                 ///< impulse, N s, >= 0 (0: no push)
  double push_duration = 0.1;                                ///< s, > 0
  double time_step = 1e-3;                                   ///< dt, s, (0, 0.01]
  double theta = 1.0;               ///< Moreau-Jean theta, [0.5, 1] (multibody/stepper.h)
  double passive_joint_theta = 1.0; ///< theta of the passive (compliant) joints, [0.5, 1]
  double duration = 0;          ///< s, >= 0; 0: the whole reference (lean, walk), 5 s (stand, drop)
  double settle_time = 1.0;     ///< s, stand: time allowed to settle before the 1 mm window
  double release_height = 0.01; ///< m, drop: the lowest contact point above the ground, >= 0
  /// drop: (joint, angle [rad] or displacement [m]) overriding the straight legs and the
  /// standing posture; empty: straight legs.
  std::vector<std::pair<std::string, double>> drop_posture;
  double fall_height = 0.4; ///< m: the run stops as failed if the waist goes below
  /// deg, (0, 180]: the run stops as failed if the waist's z axis tilts further than this from
  /// the reference waist's
  double fall_tilt = 20;
  double max_penetration = 0.005; ///< m: the run stops as failed if a contact sinks deeper
  static void declare(dealii::ParameterHandler& prm);
  void parse(dealii::ParameterHandler& prm);
};

/// Parses "x, y, yaw; x, y, yaw; ..." (m, m, rad). @p parameter names the entry in errors.
std::vector<walking::Footstep> parse_footsteps(const std::string& text,
                                               const std::string& parameter);

} // namespace plantar::app
