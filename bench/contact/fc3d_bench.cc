// fc3d_bench: Plantar's contact solvers against Siconos numerics 4.4 on Siconos-format
// FrictionContactProblem files.
//
//   fc3d_bench [--tolerance 1e-8] [--max-iterations 10000] [--newton-iterations 500]
//              [--solvers gs,admm,newton,auto,nsgs,nsn_ac] [--newton-linear auto]
//              [--warm-start START.txt] FILE.dat...
//
// --max-iterations caps GS, ADMM, auto (each of its phases) and NSGS; --newton-iterations caps
// Plantar's Newton and Siconos's NSN_AC.
//
// --newton-linear (auto, dense, sparse, woodbury) picks the linear solve of Plantar's Newton (and
// auto's Newton phase); the note says which one ran.
//
// --warm-start (one FILE only) starts every solver from the impulses of START.txt instead of
// zero: a stopped run's failed/warm_start.txt next to its failed/contact_problem.dat, the start
// the run's solve had.
//
// Prints one line per problem and solver: problem, contacts, solver, iterations, seconds, the
// error measure of Siconos (fc3d_compute_error, computed by Siconos) and status. Plantar's
// solvers are driven to Siconos's tolerance as in tests/contact/fc3d_solve.h (their own
// residual tightened by 10 while Siconos's error is above it; iterations and time summed).
#include "contact/contact_solver.h"
#include "tests/contact/fc3d_solve.h"
#include "tests/contact/siconos_format.h"
#include "tests/contact/siconos_oracle.h"

#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

using namespace plantar::contact;
using namespace plantar::contact::testing;

namespace {
struct Row {
  int iterations = 0;
  double seconds = 0.0, error = 0.0;
  std::string status, note;
};

Row run_plantar(const SiconosProblem& source, const SiconosOracle& oracle, ContactSolverType type,
                double tolerance, int max_iterations, NewtonLinearSolve linear,
                const Eigen::VectorXd* start) {
  const Fc3dSolve solve = solve_to_tolerance(
      source, type, tolerance, max_iterations,
      [&](const Eigen::VectorXd& r) { return oracle.error(r); }, linear, start);
  Row row;
  row.iterations = solve.iterations;
  row.seconds = solve.seconds;
  row.error = solve.error;
  row.status = solve.converged ? "converged" : to_string(solve.last.status);
  if (type == ContactSolverType::automatic) {
    std::ostringstream note;
    note << "finished_by=" << to_string(solve.last.finished_by)
         << " switch=" << to_string(solve.last.switch_reason) << "@" << solve.last.switch_iteration
         << " rate=" << solve.last.switch_rate;
    row.note = note.str();
  }
  if (solve.last.finished_by == ContactSolverType::newton)
    row.note += (row.note.empty() ? "" : " ") + std::string("linear=") +
                to_string(solve.last.newton_linear_solve);
  return row;
}
int run(int argc, char** argv) {
  double tolerance = 1e-8;
  int max_iterations = 10000;
  int newton_iterations = 500; // Newton-type solvers (newton, nsn_ac): an iteration costs more
  std::string solvers = "gs,admm,newton,auto,nsgs,nsn_ac";
  NewtonLinearSolve linear = NewtonLinearSolve::automatic;
  std::string warm_start_file;
  std::vector<std::string> files;
  for (int i = 1; i < argc; ++i) {
    const std::string arg = argv[i];
    if (arg == "--tolerance" && i + 1 < argc)
      tolerance = std::atof(argv[++i]);
    else if (arg == "--max-iterations" && i + 1 < argc)
      max_iterations = std::atoi(argv[++i]);
    else if (arg == "--newton-iterations" && i + 1 < argc)
      newton_iterations = std::atoi(argv[++i]);
    else if (arg == "--solvers" && i + 1 < argc)
      solvers = argv[++i];
    else if (arg == "--warm-start" && i + 1 < argc)
      warm_start_file = argv[++i];
    else if (arg == "--newton-linear" && i + 1 < argc) {
      const std::string name = argv[++i];
      bool known = false;
      for (const auto option : {NewtonLinearSolve::automatic, NewtonLinearSolve::dense,
                                NewtonLinearSolve::sparse, NewtonLinearSolve::woodbury})
        if (name == to_string(option)) {
          linear = option;
          known = true;
        }
      if (!known) {
        std::fprintf(stderr,
                     "fc3d_bench: --newton-linear %s, allowed auto, dense, sparse, "
                     "woodbury\n",
                     name.c_str());
        return 1;
      }
    } else if (!arg.empty() && arg[0] == '-') {
      std::fprintf(stderr,
                   "usage: fc3d_bench [--tolerance t] [--max-iterations n] [--newton-iterations n] "
                   "[--solvers gs,admm,newton,auto,nsgs,nsn_ac] "
                   "[--newton-linear auto|dense|sparse|woodbury] [--warm-start START.txt] "
                   "FILE.dat...\n");
      return 2;
    } else
      files.push_back(arg);
  }
  if (!warm_start_file.empty() && files.size() != 1) {
    std::fprintf(stderr, "fc3d_bench: --warm-start %s needs exactly one problem file, got %zu\n",
                 warm_start_file.c_str(), files.size());
    return 2;
  }
  if (!warm_start_file.empty())
    std::printf("# every solver starts from %s\n", warm_start_file.c_str());
  std::printf("%-34s %6s %-8s %8s %10s %10s %-15s %s\n", "problem", "n", "solver", "iter",
              "seconds", "error", "status", "note");
  std::stringstream list(solvers);
  std::vector<std::string> names;
  for (std::string name; std::getline(list, name, ',');)
    names.push_back(name);
  for (const std::string& path : files) {
    const SiconosProblem source = read_siconos_problem(path);
    const SiconosOracle oracle(path);
    const Eigen::VectorXd warm = warm_start_file.empty()
                                     ? Eigen::VectorXd()
                                     : read_warm_start(warm_start_file, source.n_contacts);
    const Eigen::VectorXd* start = warm_start_file.empty() ? nullptr : &warm;
    std::string name = path.substr(path.find_last_of('/') + 1);
    name = name.substr(0, name.rfind(".dat"));
    for (const std::string& solver : names) {
      Row row;
      if (solver == "nsgs" || solver == "nsn_ac") {
        const auto run = solver == "nsgs" ? oracle.solve(500, tolerance, max_iterations, start)
                                          : oracle.solve(504, tolerance, newton_iterations, start);
        row.iterations = run.iterations;
        row.seconds = run.seconds;
        row.error = oracle.error(run.r);
        row.status = run.info == 0 && row.error <= tolerance ? "converged" : "failed";
      } else {
        const ContactSolverType type = solver == "gs"       ? ContactSolverType::gauss_seidel
                                       : solver == "admm"   ? ContactSolverType::admm
                                       : solver == "newton" ? ContactSolverType::newton
                                                            : ContactSolverType::automatic;
        row = run_plantar(source, oracle, type, tolerance,
                          type == ContactSolverType::newton ? newton_iterations : max_iterations,
                          linear, start);
      }
      std::printf("%-34s %6d %-8s %8d %10.4g %10.3g %-15s %s\n", name.c_str(), source.n_contacts,
                  solver.c_str(), row.iterations, row.seconds, row.error, row.status.c_str(),
                  row.note.c_str());
      std::fflush(stdout);
    }
  }
  return 0;
}

} // namespace

int main(int argc, char** argv) {
  try {
    return run(argc, argv);
  } catch (const std::exception& e) { // an unreadable or malformed file: named in e.what()
    std::fprintf(stderr, "fc3d_bench: %s\n", e.what());
    return 1;
  }
}
