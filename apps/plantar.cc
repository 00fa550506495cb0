// plantar: the command-line program.
//   plantar run SCENE.prm [-o DIR]           run a scene (or a comparison of foot forms)
//   plantar sweep SCENE.prm [-o DIR] [-j N]  one run per point of subsection Sweep (also under
//                                            mpirun: apps/sweep_queue.h)
//   plantar plot DIR                         PNG figures from the CSVs under DIR
//   plantar print-parameters                 every scene parameter with default, range, help
//   plantar --help | <command> --help
#include "apps/humanoid_job.h"
#include "apps/output_directory.h"
#include "apps/parameter_listing.h"
#include "apps/scene.h"
#include "apps/static_contact_job.h"
#include "apps/static_sole_job.h"
#include "apps/sweep.h"
#include "apps/sweep_queue.h"
#include "fem/atomic_file.h"
#include "fem/exception_text.h"

#include <deal.II/base/mpi.h>

#include <cstdio>
#include <cstdlib>
#include <iostream>
#include <optional>
#include <sstream>
#include <string>
#include <vector>

namespace {

using namespace plantar;

const char* const main_help =
    R"(plantar: finite-element soles under a humanoid robot (David et al. 2008).

Usage:
  plantar run SCENE.prm [-o DIR]           run a scene; outputs (parameters.prm, summary, CSV,
                                           VTU, figures) go to DIR (default: out/<scene name>);
                                           a static contact scene also under mpirun -np N
  plantar sweep SCENE.prm [-o DIR] [-j N]  run the grid of subsection Sweep, N processes at a
                                           time (per MPI rank under mpirun); resumes an
                                           interrupted sweep
  plantar plot DIR                         PNG figures from the CSVs under DIR into DIR/figures
  plantar print-parameters                 print every scene parameter with its default, range
                                           and help
  plantar <command> --help                 help on a command

Scenes are deal.II parameter files (.prm); see scenes/ and docs/user_guide.md.
)";

const char* const run_help = R"(plantar run SCENE.prm [-o DIR] [--no-figures]

Reads SCENE.prm, checks every parameter, runs the scene and writes into DIR:
  parameters.prm   the full parameter set used (reproducibility)
  summary.txt      the figures printed at the end
  sole.vtu         the sole's fields for ParaView (static sole scene)
  contact.pvtu     static contact scene: the sole's fields for ParaView (displacement, stress,
                   contact_traction on the bottom nodes), one contact_<rank>.vtu piece per
                   MPI rank; summary.csv: DoF, ranks, iterations, forces, node states, time
                   and peak memory per rank (docs/static_contact.md); contact_nodes.csv:
                   each bottom node's force, displacement, area, pressure and state
  waist.csv        humanoid scenes: waist position, velocity, acceleration (raw and
                   filtered, Output/Accelerometer bandwidth), roll
  joints.csv       humanoid scenes: every joint's position, reference and PD torque
  contacts.csv     humanoid scenes: force and centre of pressure per foot, ZMP
  summary.csv      humanoid scenes: the summary's figures as name,value
  unconverged_solves.csv  humanoid scenes: each contact solve above Contact/Tolerance
  landings.csv     humanoid scenes: each touchdown of a foot: impulse, peak force, rise
                   time, filtered peak waist acceleration
  figures/         humanoid scenes: PNG figures (plantar plot; not with --no-figures)
A humanoid run that fails (fall, non-finite state, contact solve above
Contact/Failure residual, deep penetration, a sole past its validity) names the
step and time and what to change, writes the steps done so far to DIR/failed/
and exits with status 1; validity warnings go to the summary
(docs/reliability.md).
With Robot/Foot forms set (e.g. rigid, compliant ankle, fem sole) the scene
runs once per form into DIR/<form>/ (rigid, compliant_ankle, fem_sole) and the
figures comparing them go to DIR/figures/ (plantar plot). A form that fails
is reported with its message, its CSV up to the failure (DIR/<form>/failed/)
is plotted, the other forms still run, and the exit status is 1.
A static contact scene runs on distributed PETSc: `mpirun -np N plantar run
SCENE.prm -o DIR` spreads the sole over N ranks (DIR on a file system all ranks
share); without mpirun it runs on one. Other scene types run on one process.
A progress bar (simulated time, real-time factor) is drawn on stderr when
stdout and stderr are terminals.
Files are written to a temporary name and renamed, so a failed or killed run
leaves no half-written output; a run first removes from DIR what an earlier run
left (summaries, failed/, vtk/, *.pvd, temporary files). Exit status: 0 on success, 1 on error, 2 on bad usage.
)";

const char* const sweep_help = R"(plantar sweep SCENE.prm [-o DIR] [-j N]

Runs SCENE.prm (a humanoid scene: drop, lean, stand or walk) once per point of
the grid: Robot/Foot forms (or Robot/Foot form) x Sweep/Time steps (or
Simulation/Time step) x, for the fem sole, Sweep/Young's moduli x
Sweep/Poisson ratios (replacing E= and nu= in Sole/Materials). Each point runs
as a child process `plantar run DIR/points/<id>/scene.prm -o DIR/points/<id>`,
up to N at a time (default 1). A point is finished once its summary.csv (or
failure.txt) exists; both are written atomically, so rerunning an interrupted
sweep only computes the missing points. Writes DIR/parameters.prm,
DIR/sweep.csv (one row per point), DIR/summary.txt and DIR/figures/.
Default DIR: out/<scene name>. Exit status 1 if a point failed.
Under MPI (mpirun -np R plantar sweep ..., or srun) the points are handed out
one at a time to whichever rank has a free slot, each rank running up to N
points at a time (rank 0 included); DIR must be on a file system all ranks
share. Rank 0 writes the scene files, prints, and writes sweep.csv at the end.
See docs/cluster.md.
)";

const char* const plot_help = R"(plantar plot DIR

Draws PNG figures into DIR/figures/ from the CSVs under DIR (apps/plot/plantar_plot.py,
run with /usr/bin/python3 and matplotlib):
  a run (DIR/waist.csv ...)            waist_z, waist_velocity_z, waist_acceleration_z,
  or a comparison (DIR/<form>/...)     right_knee_torque (paper Fig. 5 to 8)
  a sweep (DIR/sweep.csv)              sweep_E_nu (Fig. 3 drop / Fig. 4 lean), sweep_time_step
Exit status 1 with a message if DIR holds none of these.
)";

const char* const print_help = R"(plantar print-parameters [--prm]

Prints every scene parameter, grouped by subsection, with its default value,
allowed range (pattern) and documentation. With --prm, prints a complete scene
file with the defaults instead.
)";

/// Swallows what ranks other than 0 would print.
std::ostream quiet(nullptr);

/// main's arguments, for MPI's initialisation by a static contact run.
int* main_argc = nullptr;
char*** main_argv = nullptr;

/// This process's rank as its MPI launcher set it (0 without a launcher): known before MPI is
/// initialised, so that only rank 0 prints a scene's errors.
int launcher_rank() {
  for (const char* name : {"OMPI_COMM_WORLD_RANK", "PMIX_RANK", "PMI_RANK"})
    if (const char* value = std::getenv(name))
      return std::atoi(value);
  return 0;
}

/// The number of ranks the launcher started (1 without a launcher).
int launcher_size() {
  for (const char* name : {"OMPI_COMM_WORLD_SIZE", "PMI_SIZE"})
    if (const char* value = std::getenv(name))
      return std::atoi(value);
  return 1;
}

/// plantar run of a static contact scene, on every rank of MPI_COMM_WORLD (MPI and PETSc are
/// initialised here, also without mpirun: one rank).
int run_static_contact_scene(const std::string& scene_file, const app::Scene& scene,
                             const dealii::ParameterHandler& prm,
                             const std::filesystem::path& out) {
  dealii::Utilities::MPI::MPI_InitFinalize mpi(*main_argc, *main_argv, 1);
  const bool rank0 = dealii::Utilities::MPI::this_mpi_process(MPI_COMM_WORLD) == 0;
  std::string error;
  if (rank0) {
    try {
      app::prepare_output_directory(out);
      std::filesystem::create_directories(out);
    } catch (const std::exception& e) {
      error = fem::exception_text(e);
    }
  }
  error = dealii::Utilities::MPI::broadcast(MPI_COMM_WORLD, error, 0);
  if (!error.empty())
    throw std::runtime_error(error);
  app::StaticContactResult result;
  try {
    result = app::run_static_contact(scene, out, MPI_COMM_WORLD);
  } catch (const std::exception& e) {
    throw std::runtime_error("scene '" + scene_file + "': " + fem::exception_text(e));
  }
  if (!rank0)
    return 0;
  std::ostringstream summary;
  summary << "scene: " << scene_file << " (" << app::to_string(scene.type) << ")\n"
          << app::format_static_contact_summary(result);
  std::cout << summary.str();
  fem::write_file_atomically(out / "parameters.prm", [&](std::ostream& os) {
    prm.print_parameters(os, dealii::ParameterHandler::PRM);
  });
  fem::write_file_atomically(out / "summary.txt", [&](std::ostream& os) { os << summary.str(); });
  // Last: its presence marks a finished run.
  fem::write_file_atomically(out / "summary.csv",
                             [&](std::ostream& os) { os << app::static_contact_csv(result); });
  std::cout << "outputs in " << out.string() << "\n";
  return 0;
}

bool wants_help(const std::vector<std::string>& args) {
  for (const auto& a : args)
    if (a == "--help" || a == "-h")
      return true;
  return false;
}

/// The -o directory, or out/<scene file stem> when none is given.
std::filesystem::path output_directory(const std::string& scene_file, const std::string& output) {
  return output.empty() ? std::filesystem::path("out") / std::filesystem::path(scene_file).stem()
                        : std::filesystem::path(output);
}

int print_parameters(const std::vector<std::string>& args) {
  if (wants_help(args)) {
    std::cout << print_help;
    return 0;
  }
  dealii::ParameterHandler prm;
  app::Scene::declare(prm);
  const bool as_prm = !args.empty() && args[0] == "--prm";
  if (as_prm)
    prm.print_parameters(std::cout, dealii::ParameterHandler::PRM);
  else
    app::print_parameter_listing(prm, std::cout);
  return 0;
}

int run(const std::vector<std::string>& args) {
  if (wants_help(args)) {
    std::cout << run_help;
    return 0;
  }
  std::string scene_file, output;
  bool figures = true;
  for (std::size_t i = 0; i < args.size(); ++i) {
    if (args[i] == "-o" && i + 1 < args.size())
      output = args[++i];
    else if (args[i] == "--no-figures")
      figures = false;
    else if (scene_file.empty() && args[i][0] != '-')
      scene_file = args[i];
    else {
      std::cerr << "plantar run: unexpected argument '" << args[i] << "'\n" << run_help;
      return 2;
    }
  }
  if (scene_file.empty()) {
    std::cerr << "plantar run: missing SCENE.prm\n" << run_help;
    return 2;
  }
  dealii::ParameterHandler prm;
  const app::Scene scene = app::load_scene(scene_file, prm);
  if (scene.type == app::SceneType::static_contact)
    return run_static_contact_scene(scene_file, scene, prm, output_directory(scene_file, output));
  if (launcher_size() > 1)
    throw std::runtime_error("scene '" + scene_file +
                             "': Scene type = " + app::to_string(scene.type) +
                             " runs on one process; only static contact runs under mpirun "
                             "with several ranks");
  // A robot that does not load fails here: once, not once per foot form, and before any output.
  if (scene.type != app::SceneType::static_sole) {
    try {
      app::check_robot(scene);
    } catch (const std::exception& e) {
      throw std::runtime_error("scene '" + scene_file + "': " + fem::exception_text(e));
    }
  }
  const std::filesystem::path out = output_directory(scene_file, output);
  app::prepare_output_directory(out);

  if (scene.type != app::SceneType::static_sole && !scene.robot.foot_forms.empty()) {
    fem::write_file_atomically(out / "parameters.prm", [&](std::ostream& os) {
      prm.print_parameters(os, dealii::ParameterHandler::PRM);
    });
    const int status = app::run_comparison(scene_file, scene, out, figures);
    std::cout << "outputs in " << out.string() << "\n";
    return status;
  }
  std::ostringstream summary;
  summary << "scene: " << scene_file << " (" << app::to_string(scene.type) << ")\n";
  app::HumanoidSummary humanoid;
  try {
    if (scene.type == app::SceneType::static_sole) {
      const auto result = app::run_static_sole(scene, out);
      summary << "sole: " << result.n_cells << " cells, " << result.n_dofs << " dofs\n"
              << "maximum displacement: " << result.max_displacement * 1e3 << " mm\n"
              << "mean vertical displacement of the bottom face: " << result.mean_bottom_uz * 1e3
              << " mm\n"
              << "reaction on the attached face: " << result.reaction_z << " N\n"
              << "wall time: " << result.wall_time << " s\n";
    } else {
      humanoid = app::run_humanoid(scene, out);
      summary << app::format_summary(scene, humanoid);
    }
  } catch (const std::exception& e) {
    throw std::runtime_error("scene '" + scene_file + "': " + fem::exception_text(e));
  }
  std::cout << summary.str();
  fem::write_file_atomically(out / "parameters.prm", [&](std::ostream& os) {
    prm.print_parameters(os, dealii::ParameterHandler::PRM);
  });
  fem::write_file_atomically(out / "summary.txt", [&](std::ostream& os) { os << summary.str(); });
  // Last: its presence marks a finished run (plantar sweep).
  if (scene.type != app::SceneType::static_sole)
    app::write_summary_csv(out / "summary.csv", humanoid);
  std::cout << "outputs in " << out.string() << "\n";
  if (figures && scene.type != app::SceneType::static_sole && scene.output.write_csv &&
      app::plot_directory(out) != 0) {
    std::cerr << "plantar run: the figures of " << out.string() << " failed\n";
    return 1;
  }
  return 0;
}

int sweep(const std::vector<std::string>& args) {
  // Under mpirun every rank parses the same arguments; only rank 0 speaks.
  const int rank = app::sweep_rank();
  std::ostream& cout = rank == 0 ? std::cout : quiet;
  std::ostream& cerr = rank == 0 ? std::cerr : quiet;
  if (wants_help(args)) {
    cout << sweep_help;
    return 0;
  }
  std::string scene_file, output;
  int jobs = 1;
  for (std::size_t i = 0; i < args.size(); ++i) {
    if (args[i] == "-o" && i + 1 < args.size())
      output = args[++i];
    else if (args[i] == "-j" && i + 1 < args.size()) {
      char* end = nullptr;
      const long n = std::strtol(args[++i].c_str(), &end, 10);
      if (*end != '\0' || n < 1 || n > 256) {
        cerr << "plantar sweep: -j " << args[i] << ": must be an integer in [1, 256]\n";
        return 2;
      }
      jobs = static_cast<int>(n);
    } else if (scene_file.empty() && args[i][0] != '-')
      scene_file = args[i];
    else {
      cerr << "plantar sweep: unexpected argument '" << args[i] << "'\n" << sweep_help;
      return 2;
    }
  }
  if (scene_file.empty()) {
    cerr << "plantar sweep: missing SCENE.prm\n" << sweep_help;
    return 2;
  }
  const auto executable = std::filesystem::read_symlink("/proc/self/exe");
  if (rank != 0)
    return app::run_sweep_worker(jobs, executable);
  const std::filesystem::path out = output_directory(scene_file, output);
  int status = 0;
  try {
    dealii::ParameterHandler prm;
    const app::Scene scene = app::load_scene(scene_file, prm);
    try {
      if (scene.type == app::SceneType::static_contact)
        throw std::invalid_argument("Scene type = static contact: plantar sweep needs a humanoid "
                                    "scene (stand, drop, lean or walk); run it with plantar run");
      if (scene.type != app::SceneType::static_sole)
        app::check_robot(scene); // once, not once per point
      status = app::run_sweep(scene_file, scene, out, jobs, executable);
    } catch (const std::exception& e) {
      throw std::runtime_error("scene '" + scene_file + "': " + fem::exception_text(e));
    }
  } catch (const std::exception& e) {
    // The message first: mpirun may end rank 0 as soon as a stopped rank exits with 1.
    std::cerr << "plantar: error: " << fem::exception_text(e) << std::endl;
    app::stop_sweep_workers(1);
    return 1;
  }
  const int plot_status = app::plot_directory(out);
  std::cout << "outputs in " << out.string() << "\n";
  return status != 0 || plot_status != 0 ? 1 : 0;
}

int plot(const std::vector<std::string>& args) {
  if (wants_help(args)) {
    std::cout << plot_help;
    return 0;
  }
  if (args.size() != 1 || args[0][0] == '-') {
    std::cerr << "plantar plot: expected one directory\n" << plot_help;
    return 2;
  }
  return app::plot_directory(args[0]) == 0 ? 0 : 1;
}

} // namespace

int main(int argc, char** argv) {
  main_argc = &argc;
  main_argv = &argv;
  std::vector<std::string> args(argv + 1, argv + argc);
  if (args.empty() || args[0] == "--help" || args[0] == "-h" || args[0] == "help") {
    std::cout << main_help;
    return args.empty() ? 2 : 0;
  }
  const std::string command = args[0];
  args.erase(args.begin());
  // MPI only for a sweep started by mpirun or srun; its points' runs never initialise it.
  std::optional<app::MpiSession> mpi;
  if (command == "sweep" && app::launched_by_mpi())
    mpi.emplace(argc, argv);
  try {
    if (command == "run")
      return run(args);
    if (command == "sweep")
      return sweep(args);
    if (command == "plot")
      return plot(args);
    if (command == "print-parameters")
      return print_parameters(args);
    std::cerr << "plantar: unknown command '" << command << "'\n" << main_help;
    return 2;
  } catch (const std::exception& e) {
    if (launcher_rank() == 0) // under mpirun: one message, not one per rank
      std::cerr << "plantar: error: " << fem::exception_text(e) << "\n";
    return 1;
  }
}
