// The static contact solve (fem/distributed_contact.h, issue 26) with each linear solver: Newton
// and GMRES iterations, time and memory per rank against the DoF, under mpirun. Prints one CSV
// line (header first) and writes the contact nodes (x, y, area, pressure) to a CSV file; never
// passes or fails (bench/README.md). The case of scenes/static_contact.prm: the sole box
// 0.2172 x 0.138 x 0.02 m (E = 4 MPa, nu = 0.3) in 11 x 7 x 1 Q1 hexahedra refined r times, the
// foot pressed 0.15 mm, tilted 0.002 rad, pushed 0.05 mm, mu = 0.5, tolerance 1e-10.
//   mpirun -np R static_contact_solver_bench REFINEMENTS mumps|amg|gamg [LINEAR_TOLERANCE]
//                                            [NODES_CSV]
#include "bench/fem/peak_memory.h"
#include "fem/distributed_contact.h"
#include "tests/fem/sole_box_grid.h"

#include <deal.II/base/mpi.h>
#include <deal.II/grid/grid_generator.h>

#include <sys/resource.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <string>

using namespace plantar;
using dealii::Point;
using dealii::Tensor;

namespace {} // namespace

int main(int argc, char** argv) {
  dealii::Utilities::MPI::MPI_InitFinalize mpi(argc, argv, 1);
  const MPI_Comm comm = MPI_COMM_WORLD;
  const bool root = dealii::Utilities::MPI::this_mpi_process(comm) == 0;
  if (argc < 3) {
    if (root)
      std::fprintf(stderr, "usage: static_contact_solver_bench REFINEMENTS mumps|amg|gamg "
                           "[LINEAR_TOLERANCE] [NODES_CSV]\n");
    return 2;
  }
  fem::DistributedContactSettings settings;
  settings.refinements = std::atoi(argv[1]);
  const std::string solver = argv[2];
  settings.linear_solver = solver == "mumps" ? fem::ContactLinearSolver::mumps
                           : solver == "amg" ? fem::ContactLinearSolver::gmres_amg
                                             : fem::ContactLinearSolver::gmres_gamg;
  if (argc > 3)
    settings.linear_tolerance = std::atof(argv[3]);
  settings.friction = 0.5;
  settings.tolerance = 1e-10;
  settings.max_iterations = 100;
  dealii::Triangulation<3> coarse;
  fem::test::make_sole_box(coarse, 11, 7, 1);
  const fem::MaterialTable materials{fem::LinearElasticMaterial(4e6, 0.3)};
  fem::RigidMotion foot;
  foot.translation = Tensor<1, 3>({0.05e-3, 0, -0.15e-3});
  foot.rotation = Tensor<1, 3>({0, 0.002, 0});
  foot.center = Point<3>(0, 0, fem::test::sole_thickness);
  const auto start = std::chrono::steady_clock::now();
  fem::DistributedContact problem(comm, coarse, materials, settings);
  try {
    problem.solve(foot);
  } catch (const std::exception& e) {
    if (root)
      std::printf("failed after %.1f s: %s\n",
                  std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count(),
                  e.what());
    return 1;
  }
  const auto& report = problem.report();
  const double wall =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  const auto max = [&](double value) { return dealii::Utilities::MPI::max(value, comm); };
  double iteration_time = 0;
  for (const double t : report.iteration_times)
    iteration_time += t / report.iteration_times.size();
  const double setup = max(problem.setup_time()), assembly = max(problem.assembly_time());
  const double solve = max(report.solve_time), per_iteration = max(iteration_time);
  const double memory = max(bench::peak_megabytes());
  const double force = problem.ground_force()[2], pressure = problem.max_pressure();
  const auto nodes = problem.gather_contact_nodes();
  if (!root)
    return 0;
  std::printf("refinements,ranks,solver,linear_tolerance,dofs,contact_nodes,newton_iterations,"
              "gmres_iterations,residual,separated,stick,slip,ground_force_z,max_pressure,setup_s,"
              "assembly_s,solve_s,iteration_s,wall_s,peak_mb_rank\n");
  std::printf("%u,%u,%s,%.3g,%u,%u,%u,%u,%.3e,%u,%u,%u,%.10g,%.10g,%.4g,%.4g,%.4g,%.4g,%.4g,%.0f\n",
              settings.refinements, dealii::Utilities::MPI::n_mpi_processes(comm), solver.c_str(),
              settings.linear_tolerance, static_cast<unsigned int>(problem.n_dofs()),
              problem.n_contact_nodes(), report.iterations, report.linear_iterations,
              report.residual, report.n_separated, report.n_stick, report.n_slip, force, pressure,
              setup, assembly, solve, per_iteration, wall, memory);
  if (argc > 4) {
    std::ofstream out(argv[4]);
    out.precision(12);
    out << "x,y,area,pressure\n";
    for (const auto& node : nodes)
      out << node.position[0] << ',' << node.position[1] << ',' << node.area << ','
          << node.force[2] / node.area << '\n';
  }
  return 0;
}
