#include "apps/sweep.h"

#include "apps/humanoid_job.h"
#include "apps/point_process.h"
#include "apps/sweep_queue.h"
#include "fem/atomic_file.h"
#include "fem/exception_text.h"

#include <chrono>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <iomanip>
#include <iostream>
#include <iterator>
#include <regex>
#include <sstream>
#include <stdexcept>

namespace plantar::app {

namespace {

namespace fs = std::filesystem;

std::string number(double value) {
  std::ostringstream out;
  out << std::setprecision(17) << value;
  return out.str();
}

std::string short_number(double value) {
  char text[32];
  std::snprintf(text, sizeof text, "%g", value);
  return text;
}

/// Sets @p value to the entry of @p axis in @p prm; throws naming the axis and the value.
void set_axis_value(dealii::ParameterHandler& prm, const SweepAxis& axis,
                    const std::string& value) {
  for (const std::string& s : axis.subsections)
    prm.enter_subsection(s);
  std::string error;
  try {
    prm.set(axis.entry, value);
  } catch (const std::exception& e) {
    error = e.what();
  }
  for (std::size_t i = 0; i < axis.subsections.size(); ++i)
    prm.leave_subsection();
  if (!error.empty())
    throw std::invalid_argument(axis.name + ": value '" + value + "' is not allowed for " +
                                axis.path() + " (plantar print-parameters gives its range)");
}

/// The complete scene file of @p point: @p scene_file with the point's general axes' values,
/// form, time step and material, absolute model and mesh paths, and no Sweep or Foot forms
/// entries.
std::string point_scene(const fs::path& scene_file, const Scene& scene, const SweepPoint& point) {
  dealii::ParameterHandler prm;
  read_scene_file(scene_file, prm);
  for (std::size_t a = 0; a < scene.sweep.axes.size(); ++a) {
    const SweepAxis& axis = scene.sweep.axes[a];
    set_axis_value(prm, axis, axis.values[point.axis_values[a]]);
  }
  prm.enter_subsection("Robot");
  prm.set("Foot form", to_string(point.form));
  prm.set("Foot forms", "");
  prm.set("URDF file", fs::absolute(scene.robot.urdf_file).string());
  prm.leave_subsection();
  prm.enter_subsection("Sole");
  prm.set("Geometry file", fs::absolute(scene.sole.geometry_file).string());
  prm.set("Materials",
          replace_material(prm.get("Materials"), point.youngs_modulus, point.poisson_ratio,
                           point.has_poisson_ratio, point.relaxation_time));
  prm.leave_subsection();
  prm.enter_subsection("Simulation");
  prm.set("Time step", number(point.time_step));
  prm.leave_subsection();
  prm.enter_subsection("Output");
  prm.set("Write VTU", false); // a sweep point needs its summary only
  prm.leave_subsection();
  prm.enter_subsection("Sweep");
  for (const char* entry : {"Young's moduli", "Poisson ratios", "Relaxation times", "Time steps"})
    prm.set(entry, "");
  for (int n = 1; n <= SweepParameters::max_axes; ++n)
    prm.set("Axis " + std::to_string(n), "");
  prm.leave_subsection();
  std::ostringstream out;
  prm.print_parameters(out, dealii::ParameterHandler::PRM);
  return out.str();
}

/// Throws std::invalid_argument naming @p point's general axes' values if its scene @p text
/// does not parse (a value out of its entry's range or at odds with another entry).
void check_point_scene(const std::string& text, const Scene& scene, const SweepPoint& point,
                       const fs::path& scene_directory) {
  if (scene.sweep.axes.empty())
    return;
  try {
    dealii::ParameterHandler prm;
    Scene::declare(prm);
    prm.parse_input_from_string(text);
    Scene parsed;
    parsed.parse(prm, scene_directory);
  } catch (const std::exception& e) {
    std::string values;
    for (std::size_t a = 0; a < scene.sweep.axes.size(); ++a)
      values += (a ? ", " : "") + scene.sweep.axes[a].name + " value '" +
                scene.sweep.axes[a].values[point.axis_values[a]] + "'";
    throw std::invalid_argument("sweep point " + point.id + " (" + values +
                                "): " + fem::exception_text(e));
  }
}

/// @p text as one CSV field (quoted when it holds a comma or a quote).
std::string csv_field(const std::string& text) {
  if (text.find_first_of(",\"\n") == std::string::npos)
    return text;
  std::string quoted = "\"";
  for (const char c : text)
    quoted += c == '"' ? std::string("\"\"") : std::string(1, c);
  return quoted + "\"";
}

} // namespace

std::string replace_material(const std::string& materials, double youngs_modulus,
                             double poisson_ratio, bool set_nu, double relaxation_time) {
  std::string result = materials;
  const std::string number_pattern = "[-+0-9.eE]+";
  if (youngs_modulus > 0)
    result = std::regex_replace(result, std::regex("\\bE\\s*=\\s*" + number_pattern),
                                "E=" + number(youngs_modulus));
  if (set_nu)
    result = std::regex_replace(result, std::regex("\\bnu\\s*=\\s*" + number_pattern),
                                "nu=" + number(poisson_ratio));
  if (relaxation_time > 0) {
    const std::regex tau("\\btau1\\s*=\\s*" + number_pattern);
    if (!std::regex_search(result, tau))
      throw std::invalid_argument("Sweep/Relaxation times: Sole/Materials = '" + materials +
                                  "' has no tau1 (a viscoelastic sole, law=prony, needed)");
    result = std::regex_replace(result, tau, "tau1=" + number(relaxation_time));
  }
  return result;
}

std::vector<SweepPoint> sweep_points(const Scene& scene) {
  std::vector<FootForm> forms = scene.robot.foot_forms;
  if (forms.empty())
    forms.push_back(scene.robot.foot_form);
  std::vector<double> steps = scene.sweep.time_steps;
  if (steps.empty())
    steps.push_back(scene.simulation.time_step);
  std::vector<double> moduli = scene.sweep.youngs_moduli, ratios = scene.sweep.poisson_ratios;
  if (moduli.empty())
    moduli.push_back(0);
  std::vector<double> taus = scene.sweep.relaxation_times;
  if (taus.empty())
    taus.push_back(0);
  std::vector<SweepPoint> points;
  for (const FootForm form : forms)
    for (const double dt : steps) {
      SweepPoint point;
      point.form = form;
      point.time_step = dt;
      const std::string base = form_directory(form) + "_dt" + short_number(dt * 1e3) + "ms";
      if (form != FootForm::fem_sole) {
        point.id = base;
        points.push_back(point);
        continue;
      }
      for (const double e : moduli) {
        point.youngs_modulus = e;
        const std::string with_e = e > 0 ? base + "_E" + short_number(e * 1e-6) + "MPa" : base;
        auto add = [&](const std::string& id) {
          for (const double tau : taus) {
            point.relaxation_time = tau;
            point.id = tau > 0 ? id + "_tau" + short_number(tau * 1e3) + "ms" : id;
            points.push_back(point);
          }
        };
        if (ratios.empty())
          add(with_e);
        for (const double nu : ratios) {
          point.poisson_ratio = nu;
          point.has_poisson_ratio = true;
          add(with_e + "_nu" + short_number(nu));
        }
      }
    }
  // The general axes: every point times every combination of their values (the last axis
  // varying fastest).
  for (const SweepAxis& axis : scene.sweep.axes) {
    std::vector<SweepPoint> expanded;
    expanded.reserve(points.size() * axis.values.size());
    for (const SweepPoint& p : points)
      for (std::size_t v = 0; v < axis.values.size(); ++v) {
        SweepPoint q = p;
        q.axis_values.push_back(v);
        q.id += "_" + axis.tag(v);
        expanded.push_back(q);
      }
    points = std::move(expanded);
  }
  return points;
}

int run_sweep(const fs::path& scene_file, const Scene& scene, const fs::path& output, int jobs,
              const fs::path& executable) {
  if (scene.type == SceneType::static_sole)
    throw std::invalid_argument("Scene type = static sole: plantar sweep needs a humanoid scene "
                                "(stand, drop, lean or walk)");
  const auto start = std::chrono::steady_clock::now();
  const std::vector<SweepPoint> points = sweep_points(scene);
  const auto done = [&](const SweepPoint& p) {
    const fs::path dir = output / "points" / p.id;
    return fs::exists(dir / "summary.csv") || fs::exists(dir / "failure.txt");
  };

  // The points' scene files, all checked before anything is written; then the sweep's
  // parameters and the scene files.
  std::vector<const SweepPoint*> pending;
  std::vector<std::string> texts;
  int n_done_before = 0;
  for (const SweepPoint& p : points) {
    if (done(p)) {
      ++n_done_before;
      continue;
    }
    texts.push_back(point_scene(scene_file, scene, p));
    check_point_scene(texts.back(), scene, p, fs::absolute(scene_file).parent_path());
    pending.push_back(&p);
  }
  {
    std::ostringstream text;
    dealii::ParameterHandler prm;
    read_scene_file(scene_file, prm);
    prm.print_parameters(text, dealii::ParameterHandler::PRM);
    fem::write_file_atomically(output / "parameters.prm",
                               [&](std::ostream& os) { os << text.str(); });
  }
  for (std::size_t i = 0; i < pending.size(); ++i)
    fem::write_file_atomically(output / "points" / pending[i]->id / "scene.prm",
                               [&](std::ostream& os) { os << texts[i]; });
  const int ranks = sweep_ranks();
  std::ostringstream processes;
  processes << jobs << " process" << (jobs > 1 ? "es" : "");
  if (ranks > 1)
    processes << " on each of " << ranks << " MPI ranks";
  std::cout << "sweep: " << points.size() << " points, " << n_done_before << " already done, "
            << pending.size() << " to run with " << processes.str() << "\n"
            << std::flush;

  // Child processes, up to `jobs` at a time (on each rank).
  int n_finished = 0;
  const auto print = [&](const SweepPoint& p, int rank, const std::string& report) {
    std::cout << "[" << ++n_finished << "/" << pending.size() << "] " << p.id;
    if (ranks > 1)
      std::cout << " (rank " << rank << ")";
    std::cout << ": " << report << "\n" << std::flush;
  };
  if (ranks > 1) {
    std::vector<fs::path> directories;
    for (const SweepPoint* p : pending)
      directories.push_back(fs::absolute(output / "points" / p->id));
    run_points_on_ranks(directories, jobs, executable, [&](const FinishedPoint& f) {
      print(*pending[static_cast<std::size_t>(f.index)], f.rank, f.report);
    });
  } else {
    PointProcesses local(executable, jobs);
    std::size_t next = 0;
    while (next < pending.size() || !local.empty()) {
      while (next < pending.size() && local.has_free_slot()) {
        local.start(static_cast<int>(next), output / "points" / pending[next]->id);
        ++next;
      }
      if (const auto f = local.reap(true))
        print(*pending[static_cast<std::size_t>(f->index)], 0, f->report);
    }
  }

  // Gather.
  std::ostringstream table, failures;
  table << "id,foot_form,time_step,E,nu,status,max_waist_acceleration_z,roll_difference_deg,"
           "max_roll_difference_deg,n_steps,mean_solver_iterations,n_unconverged,"
           "n_validity_warnings,loop_wall_time,tau1,sole_dissipated_energy";
  // The landing figures (issue 23), then one column per general axis (its entry's path).
  const char* const landing_columns[] = {"max_waist_acceleration_z_filtered", "n_landings",
                                         "max_landing_peak_force", "max_landing_impulse",
                                         "max_landing_acceleration_z"};
  for (const char* name : landing_columns)
    table << "," << name;
  for (const SweepAxis& axis : scene.sweep.axes)
    table << "," << csv_field(axis.path());
  table << "\n" << std::setprecision(17);
  const auto axis_columns = [&](const SweepPoint& p) {
    for (std::size_t a = 0; a < scene.sweep.axes.size(); ++a)
      table << "," << csv_field(scene.sweep.axes[a].values[p.axis_values[a]]);
    table << "\n";
  };
  int n_failed = 0, n_missing = 0;
  for (const SweepPoint& p : points) {
    const fs::path dir = output / "points" / p.id;
    table << p.id << "," << to_string(p.form) << "," << p.time_step << ",";
    if (p.youngs_modulus > 0)
      table << p.youngs_modulus;
    table << ",";
    if (p.has_poisson_ratio)
      table << p.poisson_ratio;
    table << ",";
    if (fs::exists(dir / "summary.csv")) {
      const fs::path s = dir / "summary.csv";
      table << "ok";
      for (const char* name :
           {"max_waist_acceleration_z", "roll_difference_deg", "max_roll_difference_deg", "n_steps",
            "mean_solver_iterations", "n_unconverged", "n_validity_warnings", "loop_wall_time"})
        table << "," << read_summary_value(s, name);
      table << ",";
      if (p.relaxation_time > 0)
        table << p.relaxation_time;
      table << "," << read_summary_value(s, "sole_dissipated_energy");
      for (const char* name : landing_columns)
        table << "," << read_summary_value(s, name);
      axis_columns(p);
      continue;
    }
    table << (fs::exists(dir / "failure.txt") ? "failed" : "missing") << ",,,,,,,,,";
    if (p.relaxation_time > 0)
      table << p.relaxation_time;
    table << ",";
    for (std::size_t i = 0; i < std::size(landing_columns); ++i)
      table << ",";
    axis_columns(p);
    if (fs::exists(dir / "failure.txt")) {
      ++n_failed;
      std::ifstream in(dir / "failure.txt");
      std::string message;
      std::getline(in, message);
      failures << "  " << p.id << ": " << message << "\n";
    } else {
      ++n_missing;
    }
  }
  fem::write_file_atomically(output / "sweep.csv", [&](std::ostream& os) { os << table.str(); });
  const double wall =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  std::ostringstream summary;
  summary << "sweep: " << scene_file.string() << " (" << to_string(scene.type) << "), "
          << points.size() << " points: " << n_done_before << " done before, " << pending.size()
          << " run now; " << n_failed << " failed, " << n_missing << " missing\n"
          << "wall time " << wall << " s with " << jobs << " process(es)";
  if (ranks > 1)
    summary << " on each of " << ranks << " MPI ranks";
  summary << "\n";
  if (n_failed)
    summary << "failed points:\n" << failures.str();
  fem::write_file_atomically(output / "summary.txt",
                             [&](std::ostream& os) { os << summary.str(); });
  std::cout << summary.str() << std::flush;
  return n_failed || n_missing ? 1 : 0;
}

} // namespace plantar::app
