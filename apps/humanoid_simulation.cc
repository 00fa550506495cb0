#include "apps/humanoid_simulation.h"

#include "apps/contact_solver_name.h"
#include "apps/scene_reference.h"
#include "apps/solver_advice.h"
#include "contact/siconos_writer.h"
#include "multibody/kinematics.h"
#include "multibody/urdf_loader.h"
#include "multibody/walking/support_polygon.h"
#include "multibody/walking/walking_reference.h"

#include <Eigen/Geometry>

#include <algorithm>

#include <chrono>
#include <cmath>
#include <limits>
#include <optional>
#include <sstream>
#include <stdexcept>

namespace plantar::app {
namespace {

using Clock = std::chrono::steady_clock;
/// N: a foot carrying more is on the ground (single support: the other foot carries less).
constexpr double min_support_load = 1.0;
double seconds_since(Clock::time_point start) {
  return std::chrono::duration<double>(Clock::now() - start).count();
}

/// @p scene itself; throws std::invalid_argument unless it is a humanoid scene with a robot.
const Scene& checked(const Scene& scene) {
  const walking::HumanoidDescription& humanoid = scene.robot.humanoid;
  if (scene.robot.urdf_file.empty())
    throw std::invalid_argument("Robot/URDF file is not set: a humanoid scene needs a robot "
                                "(e.g. 'include models/hrp2/robot.prm')");
  if (humanoid.base_link.empty() || humanoid.foot_links[0].empty() ||
      humanoid.foot_links[1].empty())
    throw std::invalid_argument(
        "Robot/Base link, Robot/Right foot link and Robot/Left foot link must name links of " +
        scene.robot.urdf_file.string() + " in a humanoid scene (docs/user_guide.md)");
  if (scene.type == SceneType::static_sole)
    throw std::invalid_argument(std::string("Scene type = ") + to_string(scene.type) +
                                ": a humanoid scene must be stand, drop, lean or walk");
  return scene;
}

/// The scene's robot with the parts of @p feet (nullptr: the bare robot of the reference).
multibody::Model build_model(const Scene& scene, const FootModel* feet) {
  const walking::HumanoidDescription& humanoid = scene.robot.humanoid;
  multibody::ModelOptions options;
  if (feet)
    feet->configure_model(options);
  multibody::Model model =
      multibody::build_model_from_urdf(scene.robot.urdf_file.string(), options);
  try {
    walking::add_sole_frames(model, humanoid);
  } catch (const std::invalid_argument& e) {
    throw std::invalid_argument(std::string("Robot: ") + e.what());
  }
  if (!model.has_free_base() || model.body_names[1] != humanoid.base_link)
    throw std::invalid_argument("Robot/Base link = '" + humanoid.base_link +
                                "': must be the root link of " + scene.robot.urdf_file.string() +
                                " ('" + (model.n_bodies > 1 ? model.body_names[1] : std::string()) +
                                "')");
  return model;
}

walking::Humanoid resolve_humanoid(const multibody::Model& model, const Scene& scene) {
  try {
    return walking::Humanoid(model, scene.robot.humanoid);
  } catch (const std::invalid_argument& e) {
    throw std::invalid_argument("Robot (" + scene.robot.urdf_file.string() + "): " + e.what());
  }
}

walking::PlannedSwing planned_swing(const Eigen::Vector2d& swing) {
  return {swing[0], swing[1]};
}

double roll_of(const Eigen::Matrix3d& rotation) {
  return std::atan2(rotation(2, 1), rotation(2, 2));
}

} // namespace

void check_robot(const Scene& scene) {
  const multibody::Model model = build_model(checked(scene), nullptr);
  resolve_humanoid(model, scene);
}

HumanoidSimulation::HumanoidSimulation(const Scene& scene)
    : scene_(checked(scene)), foot_model_(make_foot_model(scene_)),
      model_(build_model(scene_, foot_model_.get())),
      reference_model_(build_model(scene_, nullptr)), humanoid_(resolve_humanoid(model_, scene_)),
      reference_humanoid_(resolve_humanoid(reference_model_, scene_)), data_(model_) {
  const auto& sim = scene_.simulation;
  const double dt = sim.time_step;
  lift_ = foot_model_->lift();
  summary_.sole_thickness = lift_;
  pads_ = std::make_unique<PadSet>(scene_.pads.pads, scene_.simulation.time_step,
                                   scene_.output.write_vtu);
  pads_->resolve(model_);
  pad_reports_.resize(pads_->size());

  // Configuration and velocity indices of the controlled joints.
  const std::vector<std::string>& names = humanoid_.joint_names;
  for (int joint : humanoid_.joints) {
    joint_q_.push_back(model_.idx_q[joint]);
    joint_v_.push_back(model_.idx_v[joint]);
  }
  sole_frames_ = humanoid_.sole_frames;
  angles_.setZero(humanoid_.n_joints());

  try {
    terrain_ = contact::make_terrain(scene_.terrain.terrain);
  } catch (const std::invalid_argument& e) {
    throw std::invalid_argument(std::string("Terrain (Type = ") +
                                to_string(scene_.terrain.terrain.type) + "): " + e.what());
  }

  // Reference (on the robot without compliant ankles): the scene type's (scene_reference.h).
  walking::PostureParameters posture;
  posture.com_height = scene_.robot.com_height;
  posture.leg_ik = scene_.robot.leg_ik;
  SceneReference scene_reference =
      make_scene_reference({scene_, model_, humanoid_, reference_model_, reference_humanoid_,
                            *foot_model_, *pads_, *terrain_, lift_, posture});
  reference_ = std::move(scene_reference.reference);
  double duration = scene_reference.duration;
  const double initial_lift = scene_reference.initial_lift;
  lift_ += initial_lift;
  foot_model_->plan(reference_model_, reference_humanoid_, reference_);
  if (duration <= 0)
    duration = reference_.duration();
  n_steps_ = static_cast<int>(std::lround(duration / dt));
  settle_time_ = scene_reference.settle_time;

  // Stepper and feet.
  multibody::StepperParameters stepper_parameters;
  stepper_parameters.time_step = dt;
  stepper_parameters.theta = scene_.simulation.theta;
  stepper_parameters.passive_theta = scene_.simulation.passive_joint_theta;
  stepper_parameters.normal_bias.restitution = scene_.contact.restitution;
  stepper_parameters.normal_bias.position_correction = scene_.contact.position_correction;
  stepper_parameters.solver.solver = scene_.contact.solver;
  stepper_parameters.solver.tolerance = scene_.contact.tolerance;
  stepper_parameters.solver.max_iterations = scene_.contact.max_iterations;
  stepper_parameters.solver.sticking_direct = scene_.contact.sticking_direct;
  stepper_parameters.solver.sweep_skip = scene_.contact.sweep_skip;
  stepper_parameters.solver.auto_newton_stall_iterations = scene_.contact.newton_stall_iterations;
  stepper_parameters.max_contacts = foot_model_->max_contacts() + pads_->max_contacts();
  stepper_ = std::make_unique<multibody::Stepper>(model_, stepper_parameters, *terrain_);
  stepper_->set_gains(
      multibody::PdGains::Uniform(model_, scene_.control.stiffness, scene_.control.damping));
  foot_model_->attach(*stepper_, model_, sole_frames_, scene_.contact.friction);
  pads_->attach(*stepper_);
  foot_model_->summarize(summary_);
  summary_.robot_mass = model_.total_mass();
  if (scene_.control.stabilizer == StabilizerType::dcm) {
    const ControlParameters& control = scene_.control;
    walking::BalanceParameters balance = control.balance;
    auto frame = [&](const std::string& name, const std::string& fallback,
                     const std::string& parameter) {
      const std::string& used = name.empty() ? fallback : name;
      try {
        return model_.frame_id(used);
      } catch (const std::invalid_argument&) {
        throw std::invalid_argument("Control/" + parameter + " = '" + used + "': not a link of " +
                                    scene_.robot.urdf_file.string());
      }
    };
    const walking::HumanoidDescription& names = scene_.robot.humanoid;
    balance.sensors.imu_frame = frame(control.imu_frame, names.base_link, "IMU frame");
    balance.sensors.force_frames = {
        frame(control.force_frames[0], names.foot_links[0], "Right force sensor frame"),
        frame(control.force_frames[1], names.foot_links[1], "Left force sensor frame")};
    balance.sensors.encoder_q = joint_q_;
    balance.stabilizer.sole_half_size =
        Eigen::Vector2d(0.5 * scene_.sole.length - control.cop_margin,
                        0.5 * scene_.sole.width - control.cop_margin)
            .cwiseMax(0.0);
    balance.stabilizer.support_margin = control.cop_margin;
    if (control.foot_damping_rate > 0) {
      // The CoP loop: a foot rotation d theta moves the CoP by k d theta / f_z, k the servo in
      // series with the foot's tilt stiffness, so roll' = -(k / D) roll: its rate is k / D.
      const Eigen::Vector2d k_foot = summary_.foot_tilt_stiffness = foot_model_->tilt_stiffness();
      for (int axis = 0; axis < 2; ++axis)
        balance.stabilizer.tilt_damping[axis] =
            1 / (1 / control.stiffness + 1 / k_foot[axis]) / control.foot_damping_rate;
    }
    summary_.foot_damping = balance.stabilizer.tilt_damping;
    for (int axis = 0; axis < 2; ++axis)
      if (!(summary_.foot_damping[axis] > 0))
        summary_.foot_damping[axis] = balance.stabilizer.foot_damping;
    try {
      balance_ = std::make_unique<walking::BalanceController>(model_, humanoid_, balance, dt, true);
    } catch (const std::invalid_argument& e) {
      throw std::invalid_argument(std::string("Control/Stabilizer = dcm: ") + e.what());
    }
    v_previous_ = Eigen::VectorXd::Zero(model_.nv);
    acceleration_ = Eigen::VectorXd::Zero(model_.nv);
  }
  summary_.n_pads = pads_->size();
  summary_.n_pad_nodes = pads_->max_contacts();

  // Initial state: the reference at t = 0, lifted; at rest.
  q_ = model_.neutral_configuration();
  v_ = Eigen::VectorXd::Zero(model_.nv);
  tau_ = Eigen::VectorXd::Zero(model_.nv);
  v_ref_ = Eigen::VectorXd::Zero(model_.nv);
  q_ref_ = q_;
  reference_at(0.0, q_);
  // The drop (feet and pads) and a walk placed on the terrain stand on it already.
  const bool placed_on_terrain =
      scene_.type == SceneType::drop ||
      (scene_.type == SceneType::walk && scene_.walking.placement == FootstepPlacement::terrain);
  if (terrain_->level_height() != std::optional<double>(0.0) && !placed_on_terrain) {
    // The reference stands on z = 0: raise it onto the highest ground under the feet's
    // contact points at t = 0.
    multibody::forward_kinematics(model_, data_, q_);
    double highest = -std::numeric_limits<double>::infinity();
    for (int foot = 0; foot < 2; ++foot) {
      const multibody::SE3 sole = multibody::frame_placement(model_, data_, sole_frames_[foot]);
      const Eigen::Matrix3Xd& points = foot_model_->contact_points();
      for (int k = 0; k < points.cols(); ++k) {
        const Eigen::Vector3d x = sole.act_point(points.col(k));
        highest = std::max(highest, terrain_->height(x.x(), x.y()));
      }
    }
    terrain_lift_ = highest;
    lift_ += terrain_lift_;
    reference_at(0.0, q_);
  }
  q_ref_prev_ = q_;
  foot_model_->set_reference_state(0.0, q_); // e.g. compensated ankles: predicted deflection
  lift_ -= initial_lift;                     // the planned (reference) base is on the ground

  // Planned sole positions at the end (reference kinematics, lifted).
  {
    Eigen::VectorXd q_end = q_;
    reference_at(n_steps_ * dt, q_end);
    foot_model_->set_reference_state(n_steps_ * dt, q_end); // the planned feet, not the
                                                            // compensated legs' ends
    multibody::forward_kinematics(model_, data_, q_end);
    summary_.planned_right_sole =
        multibody::frame_placement(model_, data_, sole_frames_[0]).translation;
    summary_.planned_left_sole =
        multibody::frame_placement(model_, data_, sole_frames_[1]).translation;
  }

  // Output tables.
  const int rows = n_steps_ / scene_.output.output_every + 2;
  waist_ = TimeSeries({"t", "x", "y", "z", "vx", "vy", "vz", "ax", "ay", "az", "roll", "pitch",
                       "yaw", "roll_ref", "z_ref", "az_filtered"},
                      rows);
  std::vector<std::string> joint_columns{"t"};
  for (const auto& name : names)
    for (const char* suffix : {"_q", "_ref", "_tau"})
      joint_columns.push_back(name + suffix);
  joints_ = TimeSeries(joint_columns, rows);
  std::vector<std::string> contact_columns{
      "t",       "right_fx",   "right_fy",          "right_fz",       "right_copx", "right_copy",
      "left_fx", "left_fy",    "left_fz",           "left_copx",      "left_copy",  "zmp_x",
      "zmp_y",   "n_contacts", "solver_iterations", "solver_residual"};
  for (int i = 0; i < pads_->size(); ++i)
    for (const char* suffix : {"_fx", "_fy", "_fz", "_compression"})
      contact_columns.push_back(pads_->name(i) + suffix);
  contacts_ = TimeSeries(contact_columns, rows);
  if (balance_)
    balance_series_ = TimeSeries({"t",
                                  "dcm_x",
                                  "dcm_y",
                                  "dcm_ref_x",
                                  "dcm_ref_y",
                                  "true_dcm_x",
                                  "true_dcm_y",
                                  "zmp_ref_x",
                                  "zmp_ref_y",
                                  "zmp_desired_x",
                                  "zmp_desired_y",
                                  "com_x",
                                  "com_y",
                                  "com_z",
                                  "right_roll",
                                  "right_pitch",
                                  "right_dz",
                                  "left_roll",
                                  "left_pitch",
                                  "left_dz",
                                  "step_deficit_x",
                                  "step_deficit_y",
                                  "plan_shift_x",
                                  "plan_shift_y",
                                  "landing_shift_x",
                                  "landing_shift_y",
                                  "reference_time"},
                                 rows);
  unconverged_ = UnconvergedSolves(n_steps_);
  const double bandwidth = scene_.output.accelerometer_bandwidth;
  summary_.accelerometer_bandwidth = bandwidth < 0.5 / dt ? bandwidth : 0.0; // else raw
  accelerometer_ = make_butterworth_low_pass(summary_.accelerometer_bandwidth, dt,
                                             "Output/Accelerometer bandwidth");
  const double weight = summary_.robot_mass * model_.gravity.norm();
  for (LandingDetector& detector : landings_)
    detector = LandingDetector(
        {scene_.output.landing_threshold * weight, scene_.output.landing_window}, dt, n_steps_);
  summary_.time_step = dt;
  summary_.setup_wall_time = seconds_since(setup_start_);
}

HumanoidSimulation::~HumanoidSimulation() = default;

void HumanoidSimulation::reference_at(double t, Eigen::Ref<Eigen::VectorXd> q_out) {
  Eigen::Isometry3d base;
  reference_.sample(t, angles_, base);
  if (model_.has_free_base()) {
    q_out.head<3>() = base.translation();
    q_out[2] += lift_;
    const Eigen::Quaterniond rotation(base.linear());
    q_out.segment<4>(3) << rotation.x(), rotation.y(), rotation.z(), rotation.w();
  }
  for (int j = 0; j < humanoid_.n_joints(); ++j)
    q_out[joint_q_[j]] = angles_[j];
}

std::array<Eigen::Vector3d, 2> HumanoidSimulation::reference_soles(double t) {
  Eigen::VectorXd q = q_ref_;
  reference_at(t, q);
  foot_model_->set_reference_state(t, q);
  multibody::Data data(model_);
  multibody::forward_kinematics(model_, data, q);
  return {multibody::frame_placement(model_, data, sole_frames_[0]).translation,
          multibody::frame_placement(model_, data, sole_frames_[1]).translation};
}

void HumanoidSimulation::fail(const std::string& what) const {
  std::ostringstream msg;
  msg << to_string(scene_.type) << " (" << to_string(scene_.robot.foot_form) << "): step " << step_
      << ", t = " << step_ * summary_.time_step << " s: " << what;
  throw std::runtime_error(msg.str());
}

void HumanoidSimulation::step() {
  if (step_ >= n_steps_)
    return;
  const double dt = summary_.time_step;
  // The reference's time: the plan's, run faster by the step timing (step_timing.h).
  const double t_next = (step_ + 1) * dt + (balance_ ? balance_->step_timing().advance() : 0.0);
  reference_time_ = t_next;
  reference_at(t_next, q_ref_);
  if (balance_) {
    foot_model_->set_reference_state(t_next, q_ref_);
    acceleration_ = (v_ - v_previous_) / dt;
    for (int foot = 0; foot < 2; ++foot) {
      // [f; sum x × f] about the world origin, at the contact points' heights.
      const FootReport& r = foot_reports_[foot];
      ground_wrenches_[foot] << r.force, r.torque;
    }
    balance_->set_planned_ground(reference_.ground_at(t_next));
    balance_->set_planned_supports(reference_.support_at(0, t_next),
                                   reference_.support_at(1, t_next));
    balance_->set_planned_swings({planned_swing(reference_.swing_at(0, t_next)),
                                  planned_swing(reference_.swing_at(1, t_next))},
                                 t_next);
    balance_->update(q_, v_, acceleration_, ground_wrenches_, q_ref_);
    summary_.adjusted_steps = balance_->step_adjustment().adjusted_steps();
    summary_.max_step_adjustment = balance_->step_adjustment().max_adjustment();
    summary_.step_plan_shift = balance_->step_adjustment().plan_shift();
    summary_.max_landing_error = balance_->step_adjustment().max_landing_error();
    const walking::StepTiming& timing = balance_->step_timing();
    summary_.shortened_swings = timing.shortened_swings();
    summary_.max_timing_rate = timing.max_rate();
    summary_.timing_advance = timing.advance();
    for (int foot = 0; foot < 2; ++foot)
      summary_.final_anchor_shifts[foot] = balance_->step_adjustment().anchor_shift(foot);
    const walking::TouchdownAdaptation& touchdown = balance_->touchdown();
    summary_.early_touchdowns = touchdown.early_touchdowns();
    summary_.late_touchdowns = touchdown.late_touchdowns();
    summary_.max_touchdown_level =
        std::max(summary_.max_touchdown_level, touchdown.levels().cwiseAbs().maxCoeff());
    v_previous_ = v_;
  }
  const SimulationParameters& sim = scene_.simulation;
  if (sim.push_magnitude > 0) {
    const double t = step_ * dt;
    const bool pushing = t >= sim.push_time && t < sim.push_time + sim.push_duration;
    const Eigen::Quaterniond base(q_[6], q_[3], q_[4], q_[5]);
    tau_.head<3>() =
        pushing ? Eigen::Vector3d(base.toRotationMatrix().transpose() *
                                  (sim.push_magnitude / sim.push_duration) * sim.push_direction)
                : Eigen::Vector3d::Zero();
  }
  for (int j = 0; j < humanoid_.n_joints(); ++j)
    v_ref_[joint_v_[j]] = (q_ref_[joint_q_[j]] - q_ref_prev_[joint_q_[j]]) / dt;
  q_ref_prev_ = q_ref_;

  multibody::StepReport report;
  try {
    report = stepper_->step(q_, v_, tau_, q_ref_, v_ref_);
  } catch (const std::exception& e) {
    fail(std::string("stepper: ") + e.what());
  }
  ++step_;
  if (!q_.allFinite() || !v_.allFinite())
    fail("non-finite configuration or velocity");
  summary_.max_active_contacts = std::max(summary_.max_active_contacts, report.n_contacts);
  if (report.n_contacts > 0) {
    summary_.max_solver_residual = std::max(summary_.max_solver_residual, report.solver.residual);
    ++summary_.n_solves;
    summary_.n_direct_solves += report.solver.direct ? 1 : 0;
    const contact::DirectAttempt attempt = report.solver.direct_attempt;
    summary_.n_direct_refused_cone += attempt == contact::DirectAttempt::refused_cone ? 1 : 0;
    summary_.n_direct_refused_residual +=
        attempt == contact::DirectAttempt::refused_residual ? 1 : 0;
    if (attempt == contact::DirectAttempt::refused_cone ||
        attempt == contact::DirectAttempt::refused_residual)
      summary_.iterations_after_refusal += report.solver.iterations;
    summary_.n_local_solves += report.solver.n_local_solves;
    summary_.solver_iterations += report.solver.iterations;
    summary_.max_solver_iterations =
        std::max(summary_.max_solver_iterations, static_cast<int>(report.solver.iterations));
    const contact::SolverResult& solve = report.solver;
    summary_.n_switch_slow += solve.switch_reason == contact::SwitchReason::slow ? 1 : 0;
    summary_.n_switch_stalled += solve.switch_reason == contact::SwitchReason::stalled ? 1 : 0;
    summary_.n_switch_budget += solve.switch_reason == contact::SwitchReason::budget ? 1 : 0;
    summary_.n_switch_failed += solve.switch_reason == contact::SwitchReason::failed ? 1 : 0;
    if (!solve.converged()) {
      ++summary_.n_unconverged;
      unconverged_.add({step_, step_ * dt, solve.residual, report.n_contacts, solve.iterations,
                        solve.status, solve.finished_by, solve.switch_reason,
                        solve.switch_iteration});
      if (!(solve.residual <= scene_.contact.failure_residual)) {
        const ContactParameters& settings = scene_.contact;
        std::ostringstream msg;
        msg << "contact solver " << contact::to_string(solve.status) << " after "
            << solve.iterations << " iterations (" << contact_solver_name(settings.solver);
        if (solve.switch_reason != contact::SwitchReason::none)
          msg << ": gauss-seidel " << contact::to_string(solve.switch_reason) << " after "
              << solve.switch_iteration << " sweeps, then newton";
        msg << "), residual " << solve.residual << " m/s > Contact/Failure residual "
            << settings.failure_residual << " m/s, " << report.n_contacts << " contacts; "
            << solver_advice({solve, settings.solver, settings.tolerance, settings.max_iterations,
                              dt, summary_.foot_stiffness, summary_.robot_mass})
            << " (the problem is written as failed/contact_problem.dat, Siconos numerics' "
               "format, and its start as failed/warm_start.txt)";
        std::ostringstream problem, start;
        contact::write_siconos_problem(stepper_->problem(), problem);
        failed_contact_problem_ = problem.str();
        contact::write_warm_start(report.n_contacts, stepper_->warm_start(), start);
        failed_warm_start_ = start.str();
        fail(msg.str());
      }
    }
  }

  // Waist.
  const Eigen::Quaterniond base_rotation(q_[6], q_[3], q_[4], q_[5]);
  const Eigen::Matrix3d rotation = base_rotation.toRotationMatrix();
  const Eigen::Vector3d velocity = rotation * v_.head<3>();
  const Eigen::Vector3d acceleration = (velocity - waist_velocity_) / dt;
  waist_velocity_ = velocity;
  summary_.max_waist_acceleration_z =
      std::max(summary_.max_waist_acceleration_z, std::abs(acceleration.z()));
  const double acceleration_z_filtered =
      filter(accelerometer_, accelerometer_state_, acceleration.z());
  summary_.max_waist_acceleration_z_filtered =
      std::max(summary_.max_waist_acceleration_z_filtered, std::abs(acceleration_z_filtered));
  summary_.max_waist_height_error =
      std::max(summary_.max_waist_height_error, std::abs(q_[2] - q_ref_[2]));
  summary_.min_waist_height = std::min(summary_.min_waist_height, q_[2]);
  if (q_[2] < scene_.simulation.fall_height) {
    std::ostringstream msg;
    msg << "the robot fell: waist height " << q_[2] << " m < Simulation/Fall height "
        << scene_.simulation.fall_height << " m";
    fail(msg.str());
  }
  const Eigen::Quaterniond ref_rotation(q_ref_[6], q_ref_[3], q_ref_[4], q_ref_[5]);
  const Eigen::Matrix3d reference_rotation = ref_rotation.toRotationMatrix();
  const double tilt =
      std::acos(std::clamp(rotation.col(2).dot(reference_rotation.col(2)), -1.0, 1.0));
  summary_.max_waist_tilt = std::max(summary_.max_waist_tilt, tilt);
  if (tilt > scene_.simulation.fall_tilt * M_PI / 180) {
    std::ostringstream msg;
    msg << "the robot fell: waist tilted " << tilt * 180 / M_PI
        << " deg from the reference's > Simulation/Fall tilt " << scene_.simulation.fall_tilt
        << " deg";
    fail(msg.str());
  }
  const double roll = roll_of(rotation), roll_ref = roll_of(reference_rotation);
  summary_.final_roll = roll;
  summary_.commanded_roll = roll_ref;
  summary_.max_roll_difference = std::max(summary_.max_roll_difference, std::abs(roll_ref - roll));
  const double t = step_ * dt;
  if (settle_time_ > 0 && t >= settle_time_) {
    if (t - dt < settle_time_)
      settle_position_ = q_.head<3>();
    summary_.stand_window_deviation =
        std::max(summary_.stand_window_deviation, (q_.head<3>() - settle_position_).norm());
  }

  // Contacts: forces, centres of pressure, ZMP, penetration.
  multibody::forward_kinematics(model_, data_, q_);
  for (int foot = 0; foot < 2; ++foot) {
    foot_model_->report(foot, data_, dt, foot_reports_[foot]);
    summary_.max_penetration = std::max(summary_.max_penetration, foot_reports_[foot].depth);
  }
  Eigen::Vector3d pad_force = Eigen::Vector3d::Zero();
  for (int i = 0; i < pads_->size(); ++i) {
    PadReport& pad = pad_reports_[i];
    pads_->report(i, data_, pad);
    pad_force += pad.force;
    summary_.max_penetration = std::max(summary_.max_penetration, pad.depth);
    summary_.max_pad_force = std::max(summary_.max_pad_force, pad.force.norm());
    summary_.max_pad_compression = std::max(summary_.max_pad_compression, pad.compression);
    try {
      pads_->check(i, pad);
    } catch (const std::exception& e) {
      fail(e.what());
    }
  }
  summary_.final_pad_force = pad_force;
  try {
    pads_->finish_step();
  } catch (const std::exception& e) {
    fail(e.what());
  }
  summary_.pad_dissipated_energy = pads_->dissipated_energy();
  try {
    foot_model_->update(data_);
    summary_.validity.set_step(step_, t);
    foot_model_->check_validity(data_, summary_.validity);
  } catch (const std::exception& e) {
    fail(e.what());
  }
  foot_model_->summarize(summary_);
  for (int foot = 0; foot < 2; ++foot) {
    landings_[foot].update(t, foot_reports_[foot].force.z(), acceleration_z_filtered);
    if (step_ == n_steps_)
      landings_[foot].finish();
  }
  summarize_landings();
  if (summary_.max_penetration > scene_.simulation.max_penetration) {
    std::ostringstream msg;
    msg << "a contact point is " << summary_.max_penetration
        << " m deep in the ground > Simulation/Max penetration "
        << scene_.simulation.max_penetration << " m";
    fail(msg.str());
  }
  const Eigen::Vector3d& force_r = foot_reports_[0].force;
  const Eigen::Vector3d& force_l = foot_reports_[1].force;
  summary_.final_contact_force = force_r + force_l + pad_force;
  // Single support, outside the landing windows: the stance sole's CoP margin to its outline.
  for (int foot = 0; foot < 2; ++foot)
    if (!(foot_reports_[foot].force.z() > min_support_load))
      loaded_since_[foot] = -1;
    else if (loaded_since_[foot] < 0)
      loaded_since_[foot] = t;
  const bool right_loaded = loaded_since_[0] >= 0, left_loaded = loaded_since_[1] >= 0;
  if (right_loaded != left_loaded) {
    const int stance = right_loaded ? 0 : 1;
    const FootReport& foot = foot_reports_[stance];
    if (foot.force.z() > 0.1 * summary_.robot_mass * model_.gravity.norm() &&
        t - loaded_since_[stance] >= scene_.output.landing_window) {
      const multibody::SE3 sole = multibody::frame_placement(model_, data_, sole_frames_[stance]);
      int k = 0;
      for (const double sx : {-0.5, 0.5})
        for (const double sy : {-0.5, 0.5})
          support_corners_.col(k++) =
              sole.act_point(Eigen::Vector3d(sx * scene_.sole.length, sy * scene_.sole.width, 0.0))
                  .head<2>();
      const Eigen::Vector2d cop = foot.moment.head<2>() / foot.force.z();
      summary_.min_single_support_margin =
          std::min(summary_.min_single_support_margin, walking::hull_margin(cop, support_corners_));
    }
  }
  if (balance_) {
    const walking::BalanceStatistics& stats = balance_->statistics();
    summary_.max_dcm_error = stats.max_dcm_error;
    summary_.max_true_dcm_error = stats.max_true_dcm_error;
    summary_.max_dcm_estimate_error = stats.max_dcm_estimate_error;
  }
  summary_.n_steps = step_;
  summary_.simulated_time = t;
  if (step_ == n_steps_) {
    summary_.final_right_sole =
        multibody::frame_placement(model_, data_, sole_frames_[0]).translation;
    summary_.final_left_sole =
        multibody::frame_placement(model_, data_, sole_frames_[1]).translation;
  }
  if (output_hook_ && (step_ % output_every_ == 0 || step_ == n_steps_))
    output_hook_(*this);

  if (!scene_.output.write_csv || (step_ % scene_.output.output_every != 0 && step_ != n_steps_))
    return;
  const double nan = std::numeric_limits<double>::quiet_NaN();
  auto w = waist_.append();
  w << t, q_[0], q_[1], q_[2], velocity.x(), velocity.y(), velocity.z(), acceleration.x(),
      acceleration.y(), acceleration.z(), roll, std::asin(-rotation(2, 0)),
      std::atan2(rotation(1, 0), rotation(0, 0)), roll_ref, q_ref_[2], acceleration_z_filtered;
  auto jr = joints_.append();
  jr[0] = t;
  const auto& gains = stepper_->gains();
  for (int j = 0; j < humanoid_.n_joints(); ++j) {
    const int iq = joint_q_[j], iv = joint_v_[j];
    jr[1 + 3 * j] = q_[iq];
    jr[2 + 3 * j] = q_ref_[iq];
    jr[3 + 3 * j] =
        gains.stiffness[iv] * (q_ref_[iq] - q_[iq]) + gains.damping[iv] * (v_ref_[iv] - v_[iv]);
  }
  auto cr = contacts_.append();
  cr[0] = t;
  const double min_load = 1.0; // N: below it a foot's CoP is not defined (nan)
  for (int foot = 0; foot < 2; ++foot) {
    const Eigen::Vector3d& force = foot_reports_[foot].force;
    const Eigen::Vector3d& moment = foot_reports_[foot].moment;
    const int c0 = 1 + 5 * foot;
    cr[c0] = force.x();
    cr[c0 + 1] = force.y();
    cr[c0 + 2] = force.z();
    const bool loaded = force.z() > min_load;
    cr[c0 + 3] = loaded ? moment.x() / force.z() : nan;
    cr[c0 + 4] = loaded ? moment.y() / force.z() : nan;
  }
  const Eigen::Vector3d& moment_r = foot_reports_[0].moment;
  const Eigen::Vector3d& moment_l = foot_reports_[1].moment;
  const double fz = force_r.z() + force_l.z();
  cr[11] = fz > min_load ? (moment_r.x() + moment_l.x()) / fz : nan;
  cr[12] = fz > min_load ? (moment_r.y() + moment_l.y()) / fz : nan;
  cr[13] = report.n_contacts;
  cr[14] = report.solver.iterations;
  cr[15] = report.solver.residual;
  if (balance_) {
    const walking::BalanceStatistics& stats = balance_->statistics();
    const Eigen::Vector2d& dcm_ref = balance_->reference_dcm();
    const Eigen::Vector2d dcm = dcm_ref + stats.dcm_error;
    const Eigen::Vector2d true_dcm = dcm_ref + stats.true_dcm_error;
    const Eigen::Vector2d& zmp_ref = balance_->reference_zmp();
    const Eigen::Vector2d& zmp_desired = balance_->stabilizer().desired_zmp();
    const Eigen::Vector3d& com = balance_->estimator().com();
    const auto& offsets = balance_->stabilizer().offsets();
    const walking::StepAdjustment& steps = balance_->step_adjustment();
    const Eigen::Vector2d& deficit = steps.deficit();
    auto br = balance_series_.append();
    br << t, dcm.x(), dcm.y(), dcm_ref.x(), dcm_ref.y(), true_dcm.x(), true_dcm.y(), zmp_ref.x(),
        zmp_ref.y(), zmp_desired.x(), zmp_desired.y(), com.x(), com.y(), com.z(), offsets[0].roll,
        offsets[0].pitch, offsets[0].height, offsets[1].roll, offsets[1].pitch, offsets[1].height,
        deficit.x(), deficit.y(), steps.plan_shift().x(), steps.plan_shift().y(),
        steps.landing_target().x(), steps.landing_target().y(), reference_time_;
  }
  for (int i = 0; i < pads_->size(); ++i) {
    const PadReport& pad = pad_reports_[i];
    cr[16 + 4 * i] = pad.force.x();
    cr[17 + 4 * i] = pad.force.y();
    cr[18 + 4 * i] = pad.force.z();
    cr[19 + 4 * i] = pad.compression;
  }
}

void HumanoidSimulation::run(const std::function<void(const HumanoidSimulation&)>& after_step) {
  const auto start = Clock::now();
  try {
    while (step_ < n_steps_) {
      step();
      if (after_step)
        after_step(*this);
    }
  } catch (...) {
    summary_.loop_wall_time += seconds_since(start);
    throw;
  }
  summary_.loop_wall_time += seconds_since(start);
}

void HumanoidSimulation::write_csv(const std::filesystem::path& directory) const {
  std::filesystem::create_directories(directory);
  waist_.write_csv(directory / "waist.csv");
  joints_.write_csv(directory / "joints.csv");
  contacts_.write_csv(directory / "contacts.csv");
  unconverged_.write_csv(directory / "unconverged_solves.csv");
  if (balance_)
    balance_series_.write_csv(directory / "balance.csv");
  write_landings_csv(landings_[0].landings(), landings_[1].landings(), directory / "landings.csv");
}

void HumanoidSimulation::summarize_landings() {
  summary_.n_landings = 0;
  for (const LandingDetector& detector : landings_) {
    summary_.n_landings += static_cast<int>(detector.landings().size());
    if (!detector.landings().empty()) {
      const Landing& last = detector.landings().back(); // the others are already in
      summary_.max_landing_peak_force = std::max(summary_.max_landing_peak_force, last.peak_force);
      summary_.max_landing_impulse = std::max(summary_.max_landing_impulse, last.impulse);
      summary_.max_landing_acceleration_z =
          std::max(summary_.max_landing_acceleration_z, last.peak_acceleration);
    }
  }
}

} // namespace plantar::app
