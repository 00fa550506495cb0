#include "apps/humanoid_job.h"

#include "apps/output_directory.h"
#include "apps/progress.h"
#include "apps/scene_vtk_writer.h"
#include "fem/atomic_file.h"
#include "fem/exception_text.h"

#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <iostream>
#include <limits>
#include <sstream>
#include <stdexcept>
#include <sys/wait.h>
#include <unistd.h>

namespace plantar::app {

HumanoidSummary run_humanoid(const Scene& scene, const std::filesystem::path& output) {
  HumanoidSimulation simulation(scene);
  std::unique_ptr<SceneVtkWriter> vtk; // Output/Write VTU: the ParaView series from t = 0
  if (scene.output.write_vtu) {
    vtk = std::make_unique<SceneVtkWriter>(simulation, scene.robot.urdf_file,
                                           scene.output.vtk_stick_radius, output,
                                           scene.output.vtk_collection_every);
    vtk->write(simulation);
    simulation.set_output_hook(scene.output.vtk_every,
                               [&vtk](const HumanoidSimulation& s) { vtk->write(s); });
  }
  const double end_time = simulation.n_steps() * scene.simulation.time_step;
  ProgressBar progress(
      std::string(to_string(scene.type)) + " (" + to_string(scene.robot.foot_form) + ")", end_time);
  const auto show = [&](const HumanoidSimulation& s) {
    progress.update(s.steps_done() * scene.simulation.time_step);
  };
  try {
    if (progress.enabled())
      simulation.run(show);
    else
      simulation.run();
    progress.finish();
  } catch (const std::runtime_error&) {
    progress.finish();
    if (scene.output.write_csv)
      simulation.write_csv(output / "failed");
    if (const std::string& problem = simulation.failed_contact_problem(); !problem.empty()) {
      std::filesystem::create_directories(output / "failed");
      fem::write_file_atomically(output / "failed" / "contact_problem.dat",
                                 [&problem](std::ostream& os) { os << problem; });
      fem::write_file_atomically(
          output / "failed" / "warm_start.txt",
          [&simulation](std::ostream& os) { os << simulation.failed_warm_start(); });
    }
    throw;
  }
  if (vtk)
    vtk->finish();
  if (scene.output.write_csv)
    simulation.write_csv(output);
  return simulation.summary();
}

std::string format_summary(const Scene& scene, const HumanoidSummary& s) {
  std::ostringstream out;
  const double deg = 180.0 / M_PI;
  out << "foot form: " << to_string(scene.robot.foot_form);
  if (s.n_sole_nodes)
    out << " (" << s.n_sole_nodes << " contact nodes per sole)";
  out << "\n";
  if (s.sole_reduction_x > 0)
    out << "reduced sole: " << s.sole_reduction_x << " x " << s.sole_reduction_y
        << " grid, reduction error estimates: stiffness " << s.sole_reduction_estimate
        << ", pressure " << s.sole_reduction_pressure_estimate
        << " (relative; Sole/Reduction quantity)\n";
  out << "steps: " << s.n_steps << " of dt = " << s.time_step << " s, simulated "
      << s.simulated_time << " s\n"
      << "max |waist z acceleration|: " << s.max_waist_acceleration_z
      << " m/s^2 (backward difference of the step velocities), "
      << s.max_waist_acceleration_z_filtered << " m/s^2 filtered (cut-off "
      << s.accelerometer_bandwidth << " Hz; 0: raw)\n"
      << "landings: " << s.n_landings << " (landings.csv), max peak force "
      << s.max_landing_peak_force << " N, max impulse " << s.max_landing_impulse
      << " N s, max filtered |a_z| " << s.max_landing_acceleration_z << " m/s^2 in the first "
      << scene.output.landing_window * 1e3 << " ms\n"
      << "waist height: min " << s.min_waist_height << " m, max |z - z_ref| "
      << s.max_waist_height_error << " m, max tilt from the reference " << s.max_waist_tilt * deg
      << " deg\n"
      << "balance: smallest distance of the stance foot's CoP to its sole's edge in single "
         "support "
      << s.min_single_support_margin * 1e3 << " mm";
  if (scene.control.stabilizer == StabilizerType::dcm)
    out << "; DCM error up to " << s.max_dcm_error * 1e3 << " mm (estimate), "
        << s.max_true_dcm_error * 1e3 << " mm (true), estimate off the truth by up to "
        << s.max_dcm_estimate_error * 1e3 << " mm";
  out << "\n";
  if (scene.control.stabilizer == StabilizerType::dcm) {
    out << "foot admittance: damping roll " << s.foot_damping[0] << ", pitch " << s.foot_damping[1]
        << " N m s/rad";
    if (scene.control.foot_damping_rate > 0)
      out << " (Control/Foot damping rate " << scene.control.foot_damping_rate
          << " /s over the foot's tilt stiffness " << s.foot_tilt_stiffness[0] << ", "
          << s.foot_tilt_stiffness[1] << " N m/rad in series with the servo)";
    out << "; F/T low-pass " << scene.control.balance.sensors.force_bandwidth << " Hz (0: raw)\n";
  }
  if (s.sole_recondensation_tolerance > 0)
    out << "hyperelastic soles: " << s.sole_newton_checks << " Newton checks, "
        << s.sole_recondensations << " re-condensations, largest tolerated prediction error "
        << s.sole_tolerated_error << " (tolerance " << s.sole_recondensation_tolerance << ")\n";
  if (s.sole_dissipated_energy > 0)
    out << "viscoelastic soles: " << s.sole_dissipated_energy << " J dissipated (both feet)\n";
  if (s.pad_dissipated_energy > 0)
    out << "viscoelastic pads: " << s.pad_dissipated_energy << " J dissipated (all pads)\n";
  if (scene.type == SceneType::stand)
    out << "stand: max waist displacement after the settle time: " << s.stand_window_deviation * 1e3
        << " mm\n";
  if (scene.type == SceneType::lean)
    out << "lean: commanded roll " << s.commanded_roll * deg << " deg, measured "
        << s.final_roll * deg << " deg, difference " << (s.commanded_roll - s.final_roll) * deg
        << " deg (max over the run " << s.max_roll_difference * deg << " deg)\n";
  if (scene.control.balance.touchdown.enabled)
    out << "touchdown adaptation: " << s.early_touchdowns << " early, " << s.late_touchdowns
        << " late touchdowns, ground levels found up to " << s.max_touchdown_level * 1e3
        << " mm from the plan\n";
  if (scene.control.balance.step.enabled)
    out << "step adjustment: " << s.adjusted_steps << " landings moved, the largest by "
        << s.max_step_adjustment * 1e3 << " mm; the plan's shift at the end ("
        << s.step_plan_shift.x() * 1e3 << ", " << s.step_plan_shift.y() * 1e3
        << ") mm; landings up to " << s.max_landing_error * 1e3 << " mm from their targets\n";
  if (scene.control.balance.timing.enabled)
    out << "step timing: " << s.shortened_swings << " swings shortened, the reference up to "
        << s.max_timing_rate << " times the plan's rate, " << s.timing_advance * 1e3
        << " ms ahead at the end\n";
  out << "right sole at the end: " << s.final_right_sole.transpose() << " m (planned "
      << s.planned_right_sole.transpose() << ")\n"
      << "left sole at the end: " << s.final_left_sole.transpose() << " m (planned "
      << s.planned_left_sole.transpose() << ")\n"
      << "contact force at the end: " << s.final_contact_force.transpose() << " N\n";
  if (s.n_pads > 0)
    out << "pads: " << s.n_pads << " (" << s.n_pad_nodes << " contact nodes), force at the end "
        << s.final_pad_force.transpose() << " N, max force on one pad " << s.max_pad_force
        << " N, max compression " << s.max_pad_compression * 1e3 << " mm\n";
  out << "contacts: up to " << s.max_active_contacts << " active, max penetration "
      << s.max_penetration * 1e3 << " mm\n"
      << "contact solver: " << s.n_solves << " solves, iterations mean "
      << (s.n_solves ? static_cast<double>(s.solver_iterations) / s.n_solves : 0.0) << " max "
      << s.max_solver_iterations << ", " << s.n_unconverged << " unconverged"
      << (s.n_unconverged ? " (each in unconverged_solves.csv)" : "") << ", max residual "
      << s.max_solver_residual << " m/s\n";
  const int n_switches =
      s.n_switch_slow + s.n_switch_stalled + s.n_switch_budget + s.n_switch_failed;
  if (n_switches > 0)
    out << "contact solver auto: " << n_switches << " solves switched to Newton (slow "
        << s.n_switch_slow << ", stalled " << s.n_switch_stalled << ", budget " << s.n_switch_budget
        << ", failed " << s.n_switch_failed << ")\n";
  for (int i = 0; i < s.validity.size(); ++i) {
    const ValidityRecord& r = s.validity.record(i);
    out << "validity: " << r.limit.quantity << " peak " << r.peak << " at t = " << r.peak_time
        << " s (warning " << r.limit.warning << ", failure " << r.limit.failure << ")\n";
  }
  out << s.validity.warning_text() << "wall time: setup " << s.setup_wall_time << " s, loop "
      << s.loop_wall_time << " s (" << s.cost() << " s per simulated second, "
      << (s.loop_wall_time > 0 ? s.n_steps / s.loop_wall_time : 0.0) << " steps per second)\n";
  return out.str();
}

int run_comparison(const std::filesystem::path& scene_file, const Scene& scene,
                   const std::filesystem::path& output, bool figures) {
  std::ostringstream all, failures;
  all << "comparison: " << scene_file.string() << " (" << to_string(scene.type) << "), "
      << scene.robot.foot_forms.size() << " foot forms\n";
  for (const FootForm form : scene.robot.foot_forms) {
    Scene one = scene;
    one.robot.foot_form = form;
    one.robot.foot_forms.clear();
    const std::filesystem::path dir = output / form_directory(form);
    prepare_output_directory(dir);
    // The form's full parameter set.
    dealii::ParameterHandler prm;
    read_scene_file(scene_file, prm);
    prm.enter_subsection("Robot");
    prm.set("Foot form", to_string(form));
    prm.set("Foot forms", "");
    prm.leave_subsection();
    fem::write_file_atomically(dir / "parameters.prm", [&](std::ostream& os) {
      prm.print_parameters(os, dealii::ParameterHandler::PRM);
    });
    std::string text;
    try {
      const HumanoidSummary summary = run_humanoid(one, dir);
      text = format_summary(one, summary);
      write_summary_csv(dir / "summary.csv", summary);
      fem::write_file_atomically(dir / "summary.txt", [&](std::ostream& os) { os << text; });
    } catch (const std::exception& e) {
      const std::string message = fem::exception_text(e);
      text = "foot form: " + std::string(to_string(form)) + ": FAILED: " + message + "\n" +
             "(the steps done so far are in " + (dir / "failed").string() + ")\n";
      fem::write_file_atomically(dir / "failure.txt",
                                 [&](std::ostream& os) { os << message << "\n"; });
      failures << "  " << to_string(form) << ": " << message << "\n";
    }
    std::cout << text << std::flush;
    all << text;
  }
  const bool failed = !failures.str().empty();
  if (failed)
    all << "failed foot forms:\n" << failures.str();
  fem::write_file_atomically(output / "summary.txt", [&](std::ostream& os) { os << all.str(); });
  const int plot_status = figures ? plot_directory(output) : 0;
  if (failed)
    std::cerr << "plantar run: " << scene_file.string() << ": foot forms failed:\n"
              << failures.str();
  if (plot_status != 0)
    std::cerr << "plantar run: the figures of " << output.string() << " failed (plot exit status "
              << plot_status << ")\n";
  return failed || plot_status != 0 ? 1 : 0;
}

std::string form_directory(FootForm form) {
  std::string name = to_string(form);
  for (char& c : name)
    if (c == ' ')
      c = '_';
  return name;
}

void write_summary_csv(const std::filesystem::path& path, const HumanoidSummary& s) {
  const double deg = 180.0 / M_PI;
  fem::write_file_atomically(path, [&](std::ostream& out) {
    out << std::setprecision(17) << "name,value\n"
        << "time_step," << s.time_step << "\n"
        << "n_steps," << s.n_steps << "\n"
        << "simulated_time," << s.simulated_time << "\n"
        << "max_waist_acceleration_z," << s.max_waist_acceleration_z << "\n"
        << "max_waist_acceleration_z_filtered," << s.max_waist_acceleration_z_filtered << "\n"
        << "accelerometer_bandwidth," << s.accelerometer_bandwidth << "\n"
        << "n_landings," << s.n_landings << "\n"
        << "max_landing_peak_force," << s.max_landing_peak_force << "\n"
        << "max_landing_impulse," << s.max_landing_impulse << "\n"
        << "max_landing_acceleration_z," << s.max_landing_acceleration_z << "\n"
        << "min_waist_height," << s.min_waist_height << "\n"
        << "max_waist_height_error," << s.max_waist_height_error << "\n"
        << "commanded_roll_deg," << s.commanded_roll * deg << "\n"
        << "final_roll_deg," << s.final_roll * deg << "\n"
        << "roll_difference_deg," << (s.commanded_roll - s.final_roll) * deg << "\n"
        << "max_roll_difference_deg," << s.max_roll_difference * deg << "\n"
        << "max_waist_tilt_deg," << s.max_waist_tilt * deg << "\n"
        << "min_single_support_margin," << s.min_single_support_margin << "\n"
        << "max_dcm_error," << s.max_dcm_error << "\n"
        << "max_true_dcm_error," << s.max_true_dcm_error << "\n"
        << "max_dcm_estimate_error," << s.max_dcm_estimate_error << "\n"
        << "adjusted_steps," << s.adjusted_steps << "\n"
        << "max_step_adjustment," << s.max_step_adjustment << "\n"
        << "max_landing_error," << s.max_landing_error << "\n"
        << "shortened_swings," << s.shortened_swings << "\n"
        << "max_timing_rate," << s.max_timing_rate << "\n"
        << "timing_advance," << s.timing_advance << "\n"
        << "sole_thickness," << s.sole_thickness << "\n"
        << "n_solves," << s.n_solves << "\n"
        << "n_direct_solves," << s.n_direct_solves << "\n"
        << "n_direct_refused_cone," << s.n_direct_refused_cone << "\n"
        << "n_direct_refused_residual," << s.n_direct_refused_residual << "\n"
        << "iterations_after_refusal," << s.iterations_after_refusal << "\n"
        << "n_local_solves," << s.n_local_solves << "\n"
        << "mean_solver_iterations,"
        << (s.n_solves ? static_cast<double>(s.solver_iterations) / s.n_solves : 0.0) << "\n"
        << "max_solver_iterations," << s.max_solver_iterations << "\n"
        << "n_unconverged," << s.n_unconverged << "\n"
        << "n_switch_slow," << s.n_switch_slow << "\n"
        << "n_switch_stalled," << s.n_switch_stalled << "\n"
        << "n_switch_budget," << s.n_switch_budget << "\n"
        << "n_switch_failed," << s.n_switch_failed << "\n"
        << "foot_stiffness," << s.foot_stiffness << "\n"
        << "foot_roll_stiffness," << s.foot_tilt_stiffness[0] << "\n"
        << "foot_pitch_stiffness," << s.foot_tilt_stiffness[1] << "\n"
        << "foot_roll_damping," << s.foot_damping[0] << "\n"
        << "foot_pitch_damping," << s.foot_damping[1] << "\n"
        << "sole_reduction_patches_x," << s.sole_reduction_x << "\n"
        << "sole_reduction_patches_y," << s.sole_reduction_y << "\n"
        << "sole_reduction_estimate," << s.sole_reduction_estimate << "\n"
        << "sole_reduction_pressure_estimate," << s.sole_reduction_pressure_estimate << "\n"
        << "sole_reduction_reached," << s.sole_reduction_reached << "\n"
        << "n_validity_warnings," << s.validity.n_warnings() << "\n"
        << "max_solver_residual," << s.max_solver_residual << "\n"
        << "max_penetration," << s.max_penetration << "\n"
        << "sole_dissipated_energy," << s.sole_dissipated_energy << "\n"
        << "pad_dissipated_energy," << s.pad_dissipated_energy << "\n"
        << "n_pads," << s.n_pads << "\n"
        << "max_pad_force," << s.max_pad_force << "\n"
        << "max_pad_compression," << s.max_pad_compression << "\n"
        << "final_pad_force_z," << s.final_pad_force.z() << "\n"
        << "setup_wall_time," << s.setup_wall_time << "\n"
        << "loop_wall_time," << s.loop_wall_time << "\n";
    for (int i = 0; i < s.validity.size(); ++i) {
      const ValidityRecord& r = s.validity.record(i);
      out << r.limit.key << "_peak," << r.peak << "\n"
          << r.limit.key << "_warning_steps," << r.n_warning_steps << "\n";
      if (r.warned()) // no row without a warning (no NaN in outputs)
        out << r.limit.key << "_first_warning_time," << r.first_warning_time << "\n";
    }
  });
}

double read_summary_value(const std::filesystem::path& path, const std::string& name) {
  std::ifstream in(path);
  std::string line;
  while (std::getline(in, line))
    if (line.compare(0, name.size() + 1, name + ",") == 0)
      return std::stod(line.substr(name.size() + 1));
  throw std::runtime_error("'" + path.string() + "' has no value '" + name + "'");
}

int plot_directory(const std::filesystem::path& directory) {
  const std::filesystem::path script = PLANTAR_PLOT_SCRIPT;
  if (!std::filesystem::exists(script))
    throw std::runtime_error("plot script '" + script.string() + "' not found");
  std::fflush(stdout);
  const pid_t pid = ::fork();
  if (pid < 0)
    throw std::runtime_error("plot: cannot start a process");
  if (pid == 0) {
    ::execl(PLANTAR_PYTHON, PLANTAR_PYTHON, script.c_str(), directory.c_str(),
            static_cast<char*>(nullptr));
    std::fprintf(stderr, "plantar plot: cannot run %s\n", PLANTAR_PYTHON);
    ::_exit(127);
  }
  int status = 0;
  ::waitpid(pid, &status, 0);
  return WIFEXITED(status) ? WEXITSTATUS(status) : 1;
}

} // namespace plantar::app
