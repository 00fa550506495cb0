#pragma once
// The humanoid scenes (stand, drop, lean, walk): the time loop joining the multibody stepper,
// the joint reference (multibody/walking) and the feet in one of three forms (rigid points,
// compliant ankles, condensed FEM soles). Records CSV time series and the paper's figures.
//
// Per step n (t_n = n dt -> t_{n+1}):
//   q_ref = reference(t_{n+1}),  v_ref = (reference(t_{n+1}) - reference(t_n)) / dt
//   Stepper::step (implicit PD: tau = kp (q_ref - q+) + kd (v_ref - v+), the torque recorded)
//   waist velocity (world) v_w = R_base v_base,lin;  acceleration a_n = (v_w,n+1 - v_w,n) / dt
//   (backward difference of consecutive step velocities; v_w,0 = 0 at rest)
//   per foot: force F = sum p_k / dt (world), CoP = sum f_z,k x_k / sum f_z,k over its contact
//   points x_k (world, after the step); ZMP = the same over both feet (flat ground z = 0).
// Failures stop the run with std::runtime_error naming the step and time: non-finite state,
// an unconverged contact solve with residual above Contact/Failure residual, a contact deeper
// than Simulation/Max penetration, the waist below Simulation/Fall height.
// Everything is allocated by the constructor; step() allocates nothing.

#include "apps/scene.h"
#include "apps/time_series.h"
#include "multibody/data.h"
#include "multibody/model.h"
#include "multibody/stepper.h"
#include "multibody/walking/humanoid.h"
#include "multibody/walking/joint_reference.h"

#include <deal.II/grid/tria.h>

#include <Eigen/Core>

#include <array>
#include <filesystem>
#include <functional>
#include <memory>
#include <string>
#include <vector>

namespace plantar::coupling {
class CondensedSole;
class NonlinearCondensedSole;
class PadState;
} // namespace plantar::coupling

namespace plantar::app {

/// Figures of a humanoid run (SI units; accelerations in m/s^2).
struct HumanoidSummary {
  int n_steps = 0;                     ///< steps done
  double time_step = 0;                ///< s
  double simulated_time = 0;           ///< s
  double setup_wall_time = 0;          ///< s: reference, model, sole condensation
  double loop_wall_time = 0;           ///< s: the time loop
  int n_sole_nodes = 0;                ///< fem sole: contact nodes per foot
  int max_active_contacts = 0;         ///< most contact points in one step
  int n_unconverged = 0;               ///< contact solves stopped above the tolerance
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
  Eigen::Vector3d final_right_sole =
      Eigen::Vector3d::Zero(); ///< right sole frame origin (world) at end
  Eigen::Vector3d final_left_sole = Eigen::Vector3d::Zero();
  Eigen::Vector3d planned_right_sole = Eigen::Vector3d::Zero(); ///< planned (reference) at end
  Eigen::Vector3d planned_left_sole = Eigen::Vector3d::Zero();
  Eigen::Vector3d final_contact_force = Eigen::Vector3d::Zero(); ///< both feet, N, world
  // Sole/Model = hyperelastic (both feet; coupling/nonlinear_condensed_sole.h):
  int sole_newton_checks = 0;      ///< Newton solves of the soles (force changed enough)
  int sole_recondensations = 0;    ///< tangent re-condensations
  double sole_tolerated_error = 0; ///< largest prediction error accepted without re-condensing
  double sole_recondensation_tolerance = 0; ///< the scene's tolerance (0: linear sole)
  /// Wall seconds of the loop per simulated second.
  double cost() const { return simulated_time > 0 ? loop_wall_time / simulated_time : 0; }
};

class HumanoidSimulation {
public:
  /// Builds the reference, the model, the stepper and the feet for @p scene (type stand,
  /// drop, lean or walk). Throws std::invalid_argument / std::runtime_error naming the
  /// parameter or the failing part (e.g. a leg pose out of reach).
  explicit HumanoidSimulation(const Scene& scene);
  ~HumanoidSimulation();
  HumanoidSimulation(const HumanoidSimulation&) = delete;
  HumanoidSimulation& operator=(const HumanoidSimulation&) = delete;

  int n_steps() const { return n_steps_; }
  int steps_done() const { return step_; }
  /// One time step (see the file comment). No heap allocation.
  void step();
  /// All remaining steps; fills summary().loop_wall_time. @p after_step (if set) is called
  /// after every step, e.g. for a progress bar.
  void run(const std::function<void(const HumanoidSimulation&)>& after_step = nullptr);

  const HumanoidSummary& summary() const { return summary_; }
  const TimeSeries& waist_series() const { return waist_; }
  const TimeSeries& joint_series() const { return joints_; }
  const TimeSeries& contact_series() const { return contacts_; }
  /// Writes waist.csv, joints.csv, contacts.csv into @p directory (atomically).
  void write_csv(const std::filesystem::path& directory) const;
  const multibody::Model& model() const { return model_; }
  const Eigen::VectorXd& q() const { return q_; }
  /// Lift of the whole robot above the reference (m): the sole thickness for fem sole.
  double reference_lift() const { return lift_; }

  // Read-only state for output writers (apps/scene_vtk_writer.h).
  double time() const { return step_ * summary_.time_step; } ///< s
  const multibody::Stepper& stepper() const { return *stepper_; }
  /// The condensed sole (Foot form = fem sole), else nullptr.
  const coupling::CondensedSole* sole() const { return sole_.get(); }
  /// The hyperelastic sole of foot @p foot (Sole/Model = hyperelastic), else nullptr.
  const coupling::NonlinearCondensedSole* hyperelastic_sole(int foot) const {
    return hyperelastic_[foot].get();
  }
  /// The pad state (node forces, displacements) of foot @p foot (0 right, 1 left) for fem sole
  /// (linear or hyperelastic), else nullptr.
  const coupling::PadState* pad(int foot) const { return pads_[foot].get(); }
  /// Stepper patch of foot @p foot (0 right, 1 left) for fem sole (linear or hyperelastic),
  /// else -1.
  int sole_patch(int foot) const {
    return sole_ || hyperelastic_[foot] ? feet_[foot].front().patch : -1;
  }
  /// Model frame index of the right (foot 0) or left (foot 1) sole frame.
  int sole_frame(int foot) const { return sole_frames_[foot]; }
  /// Calls @p hook at the end of every step() whose count is a multiple of @p every (>= 1)
  /// and at the last step, after that step's failure checks. The hook may allocate.
  void set_output_hook(int every, std::function<void(const HumanoidSimulation&)> hook) {
    output_every_ = every;
    output_hook_ = std::move(hook);
  }

private:
  struct FootContact {
    int point = -1; ///< stepper point index, or node index of patch `patch`
    int patch = -1; ///< >= 0 for an FEM sole node
    int body = 0;
    Eigen::Vector3d position; ///< body coordinates, m
  };
  void reference_at(double t, Eigen::Ref<Eigen::VectorXd> q_out);
  [[noreturn]] void fail(const std::string& what) const;
  /// Sole/Model = hyperelastic: builds one NonlinearCondensedSole per foot on @p tria and
  /// sets the contact nodes and compliance (sole frame) of the patches.
  void build_hyperelastic_soles(const dealii::Triangulation<3>& tria,
                                const fem::PhysicalGroups& groups, Eigen::Matrix3Xd& nodes,
                                Eigen::MatrixXd& compliance);
  /// After a step: contact forces -> each hyperelastic sole; re-condensed tangents -> stepper.
  void update_hyperelastic_soles();

  Scene scene_;
  double lift_ = 0;
  multibody::Model model_;
  multibody::Model reference_model_;     ///< the robot without compliant ankles (the reference's)
  walking::Humanoid humanoid_;           ///< resolved on model_
  walking::Humanoid reference_humanoid_; ///< resolved on reference_model_
  walking::JointReference reference_;
  std::unique_ptr<coupling::CondensedSole> sole_;
  std::array<std::unique_ptr<coupling::NonlinearCondensedSole>, 2> hyperelastic_; ///< or null
  std::array<std::unique_ptr<coupling::PadState>, 2> pads_; ///< fem sole; outlive the stepper
  std::unique_ptr<multibody::Stepper> stepper_;
  multibody::Data data_;
  std::array<std::vector<FootContact>, 2> feet_; ///< right, left
  std::array<int, 2> sole_frames_{};
  std::vector<int> joint_q_, joint_v_; ///< per controlled joint
  int n_steps_ = 0, step_ = 0;
  /// Compensated compliant ankles: spring deflection at t = 0 (u, theta_p, theta_r per foot).
  Eigen::VectorXd initial_deflection_;
  int output_every_ = 1;
  std::function<void(const HumanoidSimulation&)> output_hook_;
  double settle_time_ = 0;

  // Workspaces.
  Eigen::VectorXd q_, v_, q_ref_, q_ref_prev_, v_ref_, tau_;
  Eigen::VectorXd angles_; ///< controlled joints
  Eigen::Vector3d waist_velocity_ = Eigen::Vector3d::Zero();
  Eigen::Vector3d settle_position_ = Eigen::Vector3d::Zero();
  Eigen::VectorXd sole_forces_, sole_offset_; // hyperelastic soles: 3 n_c
  Eigen::MatrixXd sole_compliance_;           // 3 n_c square
  TimeSeries waist_, joints_, contacts_;
  HumanoidSummary summary_;
};

} // namespace plantar::app
