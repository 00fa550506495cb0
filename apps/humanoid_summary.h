#pragma once
// The figures of a humanoid run (apps/humanoid_simulation.h), filled during the time loop.

#include "apps/validity_monitor.h"

#include <Eigen/Core>

#include <limits>

namespace plantar::app {

/// Figures of a humanoid run (SI units; accelerations in m/s^2).
struct HumanoidSummary {
  int n_steps = 0;            ///< steps done
  double time_step = 0;       ///< s
  double simulated_time = 0;  ///< s
  double setup_wall_time = 0; ///< s: reference, model, sole condensation
  double loop_wall_time = 0;  ///< s: the time loop
  int n_sole_nodes = 0;       ///< fem sole: contact nodes per foot
  double sole_thickness = 0;  ///< m, the foot model's lift (FootModel::lift)
  /// N/m: vertical stiffness of one foot's contact, pressed down uniformly (FEM sole:
  /// 1^T C_zz^-1 1 of its condensed compliance; compliant ankle: its linear spring); 0: rigid.
  double foot_stiffness = 0;
  /// N m/rad: the foot's tilt stiffness (roll, pitch; FootModel::tilt_stiffness, inf: rigid);
  /// with Control/Foot damping rate > 0 only, else 0.
  Eigen::Vector2d foot_tilt_stiffness = Eigen::Vector2d::Zero();
  /// N m s/rad: the stabilizer's foot damping (roll, pitch); 0 without the stabilizer.
  Eigen::Vector2d foot_damping = Eigen::Vector2d::Zero();
  /// Reduced fem sole: its grid (Sole/Reduced patches, or the one chosen by auto) and its
  /// reduction error estimates of the face's stiffness (coupling::reduction_error_estimate) and
  /// of its normal force field (coupling::pressure_error_estimate); 0 for the full sole.
  int sole_reduction_x = 0, sole_reduction_y = 0;
  double sole_reduction_estimate = 0;
  double sole_reduction_pressure_estimate = 0;
  /// Reduced patches = auto: false when no reduced grid met Sole/Reduction tolerance (the
  /// full sole ran; a warning was printed).
  bool sole_reduction_reached = true;
  double robot_mass = 0;       ///< kg
  int max_active_contacts = 0; ///< most contact points in one step
  int n_unconverged = 0;       ///< contact solves stopped above the tolerance (listed in
                               ///< unconverged_solves.csv)
  /// Contact/Solver = auto: solves that switched from Gauss-Seidel to Newton, per reason
  /// (contact::SwitchReason slow, stalled, budget, failed).
  int n_switch_slow = 0, n_switch_stalled = 0, n_switch_budget = 0, n_switch_failed = 0;
  double max_solver_residual = 0;      ///< m/s, over all solves
  int n_solves = 0;                    ///< contact solves (steps with active contacts)
  int n_direct_solves = 0;             ///< of which solved directly (every contact sticking)
  int n_direct_refused_cone = 0;       ///< direct candidate refused: a contact left its cone
  int n_direct_refused_residual = 0;   ///< direct candidate refused on the residual
  long iterations_after_refusal = 0;   ///< iterations of the solves whose candidate was refused
  long n_local_solves = 0;             ///< Gauss-Seidel local solves, summed over the solves
  long solver_iterations = 0;          ///< contact-solver iterations, summed over the solves
  int max_solver_iterations = 0;       ///< most iterations of one solve
  double max_penetration = 0;          ///< m, deepest contact point (deformed sole included)
  double max_waist_acceleration_z = 0; ///< max |a_z| of the waist over the run
  double max_waist_height_error = 0;   ///< max |z - z_ref| of the waist, m
  double min_waist_height = 1e9;       ///< m
  double stand_window_deviation = 0;   ///< max |p_waist(t) - p_waist(settle)| for t >= settle, m
  double final_roll = 0;               ///< measured waist roll at the end, rad
  double commanded_roll = 0;           ///< commanded waist roll at the end, rad
  double max_roll_difference = 0;      ///< max |commanded - measured| roll, rad
  double max_waist_tilt = 0; ///< max angle between the waist's z axis and the reference's, rad
  /// m: in single support (one foot above 1 N, carrying more than a tenth of the weight, loaded
  /// for at least Output/Landing window), the smallest signed distance of the stance foot's
  /// centre of pressure to its outline (Sole/Length x Width, projected on the ground; 0: the
  /// foot pivots on an edge) over the run; +inf when the run has no single support.
  double min_single_support_margin = std::numeric_limits<double>::infinity();
  /// m, Stabilizer = dcm (else NaN): max |xi_est - xi_ref|, max |xi_true - xi_ref| and max
  /// |xi_est - xi_true| over the run (horizontal; walking::BalanceStatistics)
  double max_dcm_error = std::numeric_limits<double>::quiet_NaN();
  double max_true_dcm_error = std::numeric_limits<double>::quiet_NaN();
  double max_dcm_estimate_error = std::numeric_limits<double>::quiet_NaN();
  /// max |a_z| of the waist accelerometer (Output/Accelerometer bandwidth) over the run
  double max_waist_acceleration_z_filtered = 0;
  /// Hz: the accelerometer's cut-off used; 0: raw (0 set, or at or above 1 / (2 dt))
  double accelerometer_bandwidth = 0;
  // Landings of both feet (apps/landing_detector.h, landings.csv):
  int n_landings = 0; ///< touchdowns detected
  // Control/Touchdown adaptation (multibody/walking/touchdown_adaptation.h):
  int early_touchdowns = 0, late_touchdowns = 0; ///< both feet
  double max_touchdown_level = 0; ///< m, largest |ground level found - plan| of a foot
  // Control/Step adjustment (multibody/walking/step_adjustment.h):
  int adjusted_steps = 0;                                    ///< landings moved by more than 1 mm
  double max_step_adjustment = 0;                            ///< m, largest move of one landing
  Eigen::Vector2d step_plan_shift = Eigen::Vector2d::Zero(); ///< m, the plan's shift S at the end
  double max_landing_error = 0; ///< m, largest |sensed landing - target| of a moved foot
  int shortened_swings = 0;     ///< step timing: swings whose reference ran faster
  double max_timing_rate = 1;   ///< step timing: the largest rate of the reference
  double timing_advance = 0;    ///< s, step timing: t_ref - t at the end
  /// m, each sole's (right, left) anchor shift at the end: where the loop takes it to be
  std::array<Eigen::Vector2d, 2> final_anchor_shifts{Eigen::Vector2d::Zero(),
                                                     Eigen::Vector2d::Zero()};
  double max_landing_peak_force = 0;     ///< N, largest peak F_z of a landing window
  double max_landing_impulse = 0;        ///< N s, largest impulse of a landing window
  double max_landing_acceleration_z = 0; ///< largest filtered |a_z| in a landing window
  Eigen::Vector3d final_right_sole =
      Eigen::Vector3d::Zero(); ///< right sole frame origin (world) at end
  Eigen::Vector3d final_left_sole = Eigen::Vector3d::Zero();
  Eigen::Vector3d planned_right_sole = Eigen::Vector3d::Zero(); ///< planned (reference) at end
  Eigen::Vector3d planned_left_sole = Eigen::Vector3d::Zero();
  Eigen::Vector3d final_contact_force = Eigen::Vector3d::Zero(); ///< feet and pads, N, world
  // Deformable pads (subsections Pad 1 ... Pad 6; apps/pad_set.h):
  int n_pads = 0;                 ///< pads of the scene
  int n_pad_nodes = 0;            ///< their contact nodes together
  double max_pad_force = 0;       ///< N, largest |force| on one pad over the run
  double max_pad_compression = 0; ///< m, largest node compression of a pad over the run
  Eigen::Vector3d final_pad_force = Eigen::Vector3d::Zero(); ///< all pads, N, world, at the end
  // Sole/Model = hyperelastic (both feet; coupling/nonlinear_condensed_sole.h):
  int sole_newton_checks = 0;      ///< Newton solves of the soles (force changed enough)
  int sole_recondensations = 0;    ///< tangent re-condensations
  double sole_tolerated_error = 0; ///< largest prediction error accepted without re-condensing
  double sole_recondensation_tolerance = 0; ///< the scene's tolerance (0: linear sole)
  /// The validity guards of the models (apps/validity_monitor.h): their warnings and peaks.
  ValidityMonitor validity;
  double sole_dissipated_energy = 0; ///< J, by viscoelastic soles (law=prony), both feet
  double pad_dissipated_energy = 0;  ///< J, by viscoelastic pads (law=prony), all pads
  /// Wall seconds of the loop per simulated second.
  double cost() const { return simulated_time > 0 ? loop_wall_time / simulated_time : 0; }
};

} // namespace plantar::app
