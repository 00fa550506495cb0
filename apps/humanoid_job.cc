#include "apps/humanoid_job.h"

#include <chrono>
#include <cmath>
#include <sstream>

namespace plantar::app {

HumanoidSummary run_humanoid(const Scene& scene, const std::filesystem::path& output) {
  HumanoidSimulation simulation(scene);
  try {
    simulation.run();
  } catch (const std::runtime_error&) {
    if (scene.output.write_csv)
      simulation.write_csv(output / "failed");
    throw;
  }
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
  out << "\n"
      << "steps: " << s.n_steps << " of dt = " << s.time_step << " s, simulated "
      << s.simulated_time << " s\n"
      << "max |waist z acceleration|: " << s.max_waist_acceleration_z
      << " m/s^2 (backward difference of the step velocities)\n"
      << "waist height: min " << s.min_waist_height << " m, max |z - z_ref| "
      << s.max_waist_height_error << " m\n";
  if (scene.type == "stand")
    out << "stand: max waist displacement after the settle time: " << s.stand_window_deviation * 1e3
        << " mm\n";
  if (scene.type == "lean")
    out << "lean: commanded roll " << s.commanded_roll * deg << " deg, measured "
        << s.final_roll * deg << " deg, difference " << (s.commanded_roll - s.final_roll) * deg
        << " deg (max over the run " << s.max_roll_difference * deg << " deg)\n";
  out << "right sole at the end: " << s.final_right_sole.transpose() << " m (planned "
      << s.planned_right_sole.transpose() << ")\n"
      << "left sole at the end: " << s.final_left_sole.transpose() << " m (planned "
      << s.planned_left_sole.transpose() << ")\n"
      << "contact force at the end: " << s.final_contact_force.transpose() << " N\n"
      << "contacts: up to " << s.max_active_contacts << " active, " << s.n_unconverged
      << " unconverged solves, max residual " << s.max_solver_residual << " m/s, max penetration "
      << s.max_penetration * 1e3 << " mm\n"
      << "wall time: setup " << s.setup_wall_time << " s, loop " << s.loop_wall_time << " s ("
      << s.cost() << " s per simulated second)\n";
  return out.str();
}

} // namespace plantar::app
