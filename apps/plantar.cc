// plantar: the command-line program.
//   plantar run SCENE.prm [-o DIR]     run a scene, write outputs to DIR
//   plantar print-parameters           every scene parameter with default, range, help
//   plantar --help | <command> --help
#include "apps/humanoid_job.h"
#include "apps/parameter_listing.h"
#include "apps/scene.h"
#include "apps/static_sole_job.h"
#include "fem/atomic_file.h"
#include "fem/exception_text.h"

#include <cstdio>
#include <iostream>
#include <sstream>
#include <string>
#include <vector>

namespace {

using namespace plantar;

const char* const main_help =
    R"(plantar: finite-element soles under a humanoid robot (David et al. 2008).

Usage:
  plantar run SCENE.prm [-o DIR]   run a scene; outputs (parameters.prm, CSV, VTU) go to DIR
                                   (default: out/<scene name>)
  plantar print-parameters         print every scene parameter with its default, range and help
  plantar <command> --help         help on a command

Scenes are deal.II parameter files (.prm); see scenes/ and docs/user_guide.md.
)";

const char* const run_help = R"(plantar run SCENE.prm [-o DIR]

Reads SCENE.prm, checks every parameter, runs the scene and writes into DIR:
  parameters.prm   the full parameter set used (reproducibility)
  summary.txt      the figures printed at the end
  sole.vtu         the sole's fields for ParaView (static sole scene)
  waist.csv        humanoid scenes: waist position, velocity, acceleration, roll
  joints.csv       humanoid scenes: every joint's position, reference and PD torque
  contacts.csv     humanoid scenes: force and centre of pressure per foot, ZMP
A humanoid run that fails (fall, non-finite state, unconverged contact solve,
deep penetration) names the step and time, writes the steps done so far to
DIR/failed/ and exits with status 1.
Files are written to a temporary name and renamed, so a failed run leaves no
half-written output. Exit status: 0 on success, 1 on error, 2 on bad usage.
)";

const char* const print_help = R"(plantar print-parameters [--prm]

Prints every scene parameter, grouped by subsection, with its default value,
allowed range (pattern) and documentation. With --prm, prints a complete scene
file with the defaults instead.
)";

bool wants_help(const std::vector<std::string>& args) {
  for (const auto& a : args)
    if (a == "--help" || a == "-h")
      return true;
  return false;
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
  for (std::size_t i = 0; i < args.size(); ++i) {
    if (args[i] == "-o" && i + 1 < args.size())
      output = args[++i];
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
  const std::filesystem::path out =
      output.empty() ? std::filesystem::path("out") / std::filesystem::path(scene_file).stem()
                     : std::filesystem::path(output);

  std::ostringstream summary;
  summary << "scene: " << scene_file << " (" << scene.type << ")\n";
  try {
    if (scene.type == "static sole") {
      const auto result = app::run_static_sole(scene, out);
      summary << "sole: " << result.n_cells << " cells, " << result.n_dofs << " dofs\n"
              << "maximum displacement: " << result.max_displacement * 1e3 << " mm\n"
              << "mean vertical displacement of the bottom face: " << result.mean_bottom_uz * 1e3
              << " mm\n"
              << "reaction on the attached face: " << result.reaction_z << " N\n"
              << "wall time: " << result.wall_time << " s\n";
    } else {
      summary << app::format_summary(scene, app::run_humanoid(scene, out));
    }
  } catch (const std::exception& e) {
    throw std::runtime_error("scene '" + scene_file + "': " + fem::exception_text(e));
  }
  std::cout << summary.str();
  fem::write_file_atomically(out / "parameters.prm", [&](std::ostream& os) {
    prm.print_parameters(os, dealii::ParameterHandler::PRM);
  });
  fem::write_file_atomically(out / "summary.txt", [&](std::ostream& os) { os << summary.str(); });
  std::cout << "outputs in " << out.string() << "\n";
  return 0;
}

} // namespace

int main(int argc, char** argv) {
  std::vector<std::string> args(argv + 1, argv + argc);
  if (args.empty() || args[0] == "--help" || args[0] == "-h" || args[0] == "help") {
    std::cout << main_help;
    return args.empty() ? 2 : 0;
  }
  const std::string command = args[0];
  args.erase(args.begin());
  try {
    if (command == "run")
      return run(args);
    if (command == "print-parameters")
      return print_parameters(args);
    std::cerr << "plantar: unknown command '" << command << "'\n" << main_help;
    return 2;
  } catch (const std::exception& e) {
    std::cerr << "plantar: error: " << fem::exception_text(e) << "\n";
    return 1;
  }
}
