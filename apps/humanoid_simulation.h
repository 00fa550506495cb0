#pragma once
// The humanoid scenes (stand, drop, lean, walk): the time loop joining the multibody stepper,
// the joint reference (multibody/walking) and the feet (a FootModel: apps/foot_model.h).
// Records CSV time series and the paper's figures.
//
// Per step n (t_n = n dt -> t_{n+1}):
//   q_ref = reference(t_{n+1})
//   Control/Stabilizer = dcm: q_ref += the balance loop's leg offsets from the sensors at t_n
//   (multibody/walking/balance_controller.h; the feet's wrenches of step n-1, the acceleration
//   (v_n - v_n-1) / dt)
//   v_ref = (q_ref,n+1 - q_ref,n) / dt
//   Simulation/Push magnitude > 0: a constant force on the base origin during the push
//   Stepper::step (implicit PD: tau = kp (q_ref - q+) + kd (v_ref - v+), the torque recorded)
//   waist velocity (world) v_w = R_base v_base,lin;  acceleration a_n = (v_w,n+1 - v_w,n) / dt
//   (backward difference of consecutive step velocities; v_w,0 = 0 at rest); the
//   accelerometer's a_z = Output/Accelerometer bandwidth low-pass of a_z,n
//   (apps/butterworth_low_pass.h)
//   per foot: landings from its F_z and the filtered a_z (apps/landing_detector.h)
//   per foot: force F = sum p_k / dt (world), CoP = sum f_z,k x_k / sum f_z,k over its contact
//   points x_k (world, after the step); ZMP = the same over both feet (flat ground z = 0);
//   per pad (Pad 1 ... Pad 6, apps/pad_set.h): its force and compression (not in the ZMP).
// Failures stop the run with std::runtime_error naming the step and time: non-finite state,
// an unconverged contact solve with residual above Contact/Failure residual (with what to
// change: apps/solver_advice.h), a contact deeper than Simulation/Max penetration, the waist
// below Simulation/Fall height, a pad compressed beyond its Max compression, a foot model past
// a failure level of its validity (FootModel::check_validity, apps/validity_monitor.h; past a
// warning level it is recorded in the summary). Every unconverged solve is listed
// (unconverged_solves(), unconverged_solves.csv).
// Everything is allocated by the constructor; step() allocates nothing.

#include "apps/butterworth_low_pass.h"
#include "apps/foot_model.h"
#include "apps/humanoid_summary.h"
#include "apps/landing_detector.h"
#include "apps/pad_set.h"
#include "apps/scene.h"
#include "apps/time_series.h"
#include "apps/unconverged_solves.h"
#include "contact/terrain.h"
#include "multibody/data.h"
#include "multibody/model.h"
#include "multibody/stepper.h"
#include "multibody/walking/balance_controller.h"
#include "multibody/walking/humanoid.h"
#include "multibody/walking/joint_reference.h"

#include <Eigen/Core>

#include <array>
#include <chrono>
#include <filesystem>
#include <functional>
#include <memory>
#include <string>
#include <vector>

namespace plantar::app {

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
  /// The contact solves that stopped above Contact/Tolerance, in step order.
  const UnconvergedSolves& unconverged_solves() const { return unconverged_; }
  /// The contact problem of a solve that stopped the run (Contact/Failure residual), in Siconos
  /// numerics' text format (contact/siconos_writer.h); empty when none did.
  const std::string& failed_contact_problem() const { return failed_contact_problem_; }
  /// That solve's start (the stepper's warm start, contact/siconos_writer.h write_warm_start);
  /// empty when no solve stopped the run.
  const std::string& failed_warm_start() const { return failed_warm_start_; }
  /// The landings of the right (0) and left (1) foot so far (a window still open at the end
  /// of run() is closed there).
  const std::vector<Landing>& landings(int foot) const { return landings_[foot].landings(); }
  /// Writes waist.csv, joints.csv, contacts.csv, unconverged_solves.csv, landings.csv (and, with
  /// Control/Stabilizer = dcm, balance.csv: estimated, reference and true DCM, reference and
  /// desired ZMP, estimated CoM, foot offsets) into @p directory (atomically).
  void write_csv(const std::filesystem::path& directory) const;
  const multibody::Model& model() const { return model_; }
  const Eigen::VectorXd& q() const { return q_; }
  /// Lift of the whole robot above the reference (m): the sole thickness for fem sole.
  double reference_lift() const { return lift_; }

  // Read-only state for output writers (apps/scene_vtk_writer.h).
  double time() const { return step_ * summary_.time_step; } ///< s
  const multibody::Stepper& stepper() const { return *stepper_; }
  /// The ground (subsection Terrain).
  const contact::Terrain& terrain() const { return *terrain_; }
  /// Height (m) by which the reference was raised to stand on the terrain at t = 0: the
  /// highest ground under the feet's contact points (0 on the default ground z = 0).
  double terrain_lift() const { return terrain_lift_; }
  /// The feet: their contacts, sole frames and fields.
  const FootModel& foot_model() const { return *foot_model_; }
  /// The ground's force and moments on foot @p foot (0 right, 1 left) over the last step.
  const FootReport& foot_report(int foot) const { return foot_reports_[foot]; }
  /// The deformable pads (possibly none).
  const PadSet& pads() const { return *pads_; }
  /// The balance loop of Control/Stabilizer = dcm (sensors, estimator, stabilizer); nullptr
  /// for none.
  const walking::BalanceController* balance() const { return balance_.get(); }
  /// The reference's sole frame origins (right, left; world, m) at time @p t as the balance
  /// loop reads them: the reference configuration with the foot form's own coordinates at the
  /// plan's state (FootModel::set_reference_state). For tests and diagnostics (allocates).
  std::array<Eigen::Vector3d, 2> reference_soles(double t);
  /// Calls @p hook at the end of every step() whose count is a multiple of @p every (>= 1)
  /// and at the last step, after that step's failure checks. The hook may allocate.
  void set_output_hook(int every, std::function<void(const HumanoidSimulation&)> hook) {
    output_every_ = every;
    output_hook_ = std::move(hook);
  }

private:
  void reference_at(double t, Eigen::Ref<Eigen::VectorXd> q_out);
  [[noreturn]] void fail(const std::string& what) const;
  void summarize_landings(); ///< the landing figures of summary_
  std::chrono::steady_clock::time_point setup_start_ = std::chrono::steady_clock::now();
  Scene scene_;
  std::unique_ptr<FootModel> foot_model_;
  double lift_ = 0;
  double reference_time_ = 0; ///< s, the time q_ref_ was sampled at (step timing: ahead of t)
  multibody::Model model_;
  multibody::Model reference_model_;     ///< the robot without compliant ankles (the reference's)
  walking::Humanoid humanoid_;           ///< resolved on model_
  walking::Humanoid reference_humanoid_; ///< resolved on reference_model_
  walking::JointReference reference_;
  std::unique_ptr<contact::Terrain> terrain_; ///< before stepper_, which refers to it
  double terrain_lift_ = 0;
  std::unique_ptr<multibody::Stepper> stepper_;
  multibody::Data data_;
  std::unique_ptr<PadSet> pads_;
  std::unique_ptr<walking::BalanceController> balance_;
  std::array<int, 2> sole_frames_{};
  std::vector<int> joint_q_, joint_v_; ///< per controlled joint
  int n_steps_ = 0, step_ = 0;
  int output_every_ = 1;
  std::function<void(const HumanoidSimulation&)> output_hook_;
  double settle_time_ = 0;

  // Workspaces.
  Eigen::VectorXd q_, v_, q_ref_, q_ref_prev_, v_ref_, tau_;
  Eigen::VectorXd angles_;                    ///< controlled joints
  Eigen::VectorXd v_previous_, acceleration_; ///< balance loop: v_n-1, (v_n - v_n-1) / dt
  std::array<multibody::Vector6d, 2> ground_wrenches_{}; ///< balance loop, per foot
  Eigen::Vector3d waist_velocity_ = Eigen::Vector3d::Zero();
  ButterworthLowPass accelerometer_; ///< Output/Accelerometer bandwidth
  ButterworthState accelerometer_state_;
  Eigen::Matrix<double, 2, 4> support_corners_;    ///< the stance sole's corners (its CoP margin)
  std::array<double, 2> loaded_since_{-1.0, -1.0}; ///< s, each foot above 1 N since; -1: not
  std::array<LandingDetector, 2> landings_;        ///< right, left
  Eigen::Vector3d settle_position_ = Eigen::Vector3d::Zero();
  std::array<FootReport, 2> foot_reports_; ///< right, left: the last step's
  std::vector<PadReport> pad_reports_;     ///< per pad: the last step's
  TimeSeries waist_, joints_, contacts_;
  TimeSeries balance_series_; ///< Stabilizer = dcm only (balance.csv)
  UnconvergedSolves unconverged_;
  std::string failed_contact_problem_, failed_warm_start_;
  HumanoidSummary summary_;
};

/// Loads @p scene's robot once (URDF, base and foot links, the humanoid's joints) without
/// simulating: throws std::invalid_argument naming the file and parameter if it does not load.
/// A comparison calls it before its foot forms, so a bad robot is reported once.
void check_robot(const Scene& scene);

} // namespace plantar::app
