#include "apps/static_contact_job.h"
#include "apps/static_sole_job.h"

#include "fem/atomic_file.h"
#include "fem/distributed_contact.h"
#include "fem/exception_text.h"
#include "fem/field_output.h"
#include "fem/foot_load_control.h"
#include "fem/material_table.h"
#include "fem/mesh_generator.h"
#include "fem/mesh_import.h"

#include <deal.II/base/mpi.h>
#include <deal.II/base/utilities.h>
#include <deal.II/numerics/data_out.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <sstream>
#include <stdexcept>

namespace plantar::app {

namespace {

/// Cells a static contact run may have: a cluster-size problem (docs/static_contact.md: 137k
/// DoF take 2.4 GB with MUMPS), refused beyond as a mistyped refinement or mesh size.
constexpr double kMaxCells = 5e7;

/// The sole's mesh: generated (gmsh) on rank 0 first, so that the ranks never write the cache
/// at once, then imported on every rank. A failure on rank 0 is thrown on every rank.
fem::PhysicalGroups load_mesh(const Scene& scene, MPI_Comm communicator,
                              dealii::Triangulation<3>& tria) {
  auto request = scene.sole.mesh_request();
  if (request.cache_directory.empty())
    request.cache_directory = fem::default_mesh_cache();
  std::string error;
  if (dealii::Utilities::MPI::this_mpi_process(communicator) == 0) {
    try {
      fem::generate_mesh(request);
    } catch (const std::exception& e) {
      error = fem::exception_text(e);
    }
  }
  error = dealii::Utilities::MPI::broadcast(communicator, error, 0);
  if (!error.empty())
    throw std::runtime_error(error);
  return fem::import_mesh(fem::generate_mesh(request), {"top", "bottom"}, tria);
}

std::vector<double> gather(double value, MPI_Comm communicator) {
  return dealii::Utilities::MPI::all_gather(communicator, value);
}

/// contact_<rank>.vtu on every rank, then contact.pvtu on rank 0 (each file written atomically).
void write_fields(const fem::DistributedContact& problem, const std::filesystem::path& output) {
  const MPI_Comm communicator = problem.communicator();
  const unsigned int rank = dealii::Utilities::MPI::this_mpi_process(communicator);
  const unsigned int n_ranks = dealii::Utilities::MPI::n_mpi_processes(communicator);
  dealii::DataOut<3> data_out;
  data_out.attach_dof_handler(problem.dof_handler());
  const std::vector<dealii::DataComponentInterpretation::DataComponentInterpretation> vector(
      3, dealii::DataComponentInterpretation::component_is_part_of_vector);
  data_out.add_data_vector(problem.ghosted_solution(), std::vector<std::string>(3, "displacement"),
                           dealii::DataOut<3>::type_dof_data, vector);
  data_out.add_data_vector(problem.ghosted_traction(),
                           std::vector<std::string>(3, "contact_traction"),
                           dealii::DataOut<3>::type_dof_data, vector);
  const fem::StressPostprocessor stress(problem.materials());
  data_out.add_data_vector(problem.ghosted_solution(), stress);
  dealii::Vector<float> subdomain(problem.triangulation().n_active_cells());
  subdomain = static_cast<float>(problem.triangulation().locally_owned_subdomain());
  data_out.add_data_vector(subdomain, "subdomain", dealii::DataOut<3>::type_cell_data);
  const unsigned int degree = problem.dof_handler().get_fe().degree;
  data_out.build_patches(problem.mapping(), degree);
  const std::string piece = "contact_" + std::to_string(rank) + ".vtu";
  fem::write_file_atomically(output / piece, [&](std::ostream& os) { data_out.write_vtu(os); });
  MPI_Barrier(communicator);
  if (rank == 0) {
    std::vector<std::string> pieces;
    for (unsigned int r = 0; r < n_ranks; ++r)
      pieces.push_back("contact_" + std::to_string(r) + ".vtu");
    fem::write_file_atomically(output / "contact.pvtu",
                               [&](std::ostream& os) { data_out.write_pvtu_record(os, pieces); });
  }
}

} // namespace

StaticContactResult run_static_contact(const Scene& scene, const std::filesystem::path& output,
                                       MPI_Comm communicator) {
  const auto start = std::chrono::steady_clock::now();
  const auto& parameters = scene.static_contact;
  if (scene.sole.cell_kind != fem::CellKind::hexahedron)
    throw std::invalid_argument("Sole/Cell kind = tetrahedron: the static contact scene needs "
                                "hexahedra (parallel::distributed::Triangulation refines "
                                "hexahedra only); set Sole/Cell kind = hexahedron");
  dealii::Triangulation<3> coarse;
  const auto groups = load_mesh(scene, communicator, coarse);
  const double n_cells = coarse.n_active_cells() * std::pow(8.0, parameters.refinements);
  if (n_cells > kMaxCells) {
    std::ostringstream msg;
    msg << "Static contact/Refinements = " << parameters.refinements << " on the "
        << coarse.n_active_cells() << " cells of Sole/Mesh size = " << scene.sole.mesh_size
        << " gives " << n_cells << " cells: at most " << kMaxCells
        << " (about 2e8 DoF in Q1); refine less or mesh coarser";
    throw std::invalid_argument(msg.str());
  }
  const fem::MaterialTable materials = sole_material_table(scene, groups);
  // The ground and the rotation point from the unloaded mesh.
  dealii::Point<3> lower, upper;
  for (unsigned int d = 0; d < 3; ++d) {
    lower[d] = std::numeric_limits<double>::max();
    upper[d] = -std::numeric_limits<double>::max();
  }
  for (const auto& vertex : coarse.get_vertices())
    for (unsigned int d = 0; d < 3; ++d) {
      lower[d] = std::min(lower[d], vertex[d]);
      upper[d] = std::max(upper[d], vertex[d]);
    }

  fem::DistributedContactSettings settings;
  settings.attached_boundary = groups.surface("top");
  settings.contact_boundary = groups.surface("bottom");
  settings.degree = scene.sole.degree;
  settings.refinements = parameters.refinements;
  settings.friction = parameters.friction;
  settings.ground_height = lower[2] - parameters.initial_offset;
  settings.tolerance = parameters.tolerance;
  settings.max_iterations = parameters.max_iterations;
  settings.linear_solver = parameters.linear_solver;
  fem::DistributedContact problem(communicator, coarse, materials, settings);

  fem::RigidMotion foot;
  for (unsigned int d = 0; d < 3; ++d) {
    foot.translation[d] = parameters.translation[d];
    foot.rotation[d] = parameters.rotation[d];
  }
  foot.center = dealii::Point<3>(0.5 * (lower[0] + upper[0]) + parameters.rotation_point[0],
                                 0.5 * (lower[1] + upper[1]) + parameters.rotation_point[1],
                                 upper[2] + parameters.rotation_point[2]);
  StaticContactResult result;
  if (parameters.control == FootControl::force) {
    fem::FootLoad load;
    load.normal_force = parameters.normal_force;
    load.moment_x = parameters.moment_x;
    load.moment_y = parameters.moment_y;
    fem::FootLoadSettings load_settings;
    load_settings.tolerance = parameters.load_tolerance;
    const auto load_report = fem::solve_for_foot_load(problem, load, load_settings, foot);
    result.load_iterations = load_report.iterations;
    result.contact_solves = load_report.contact_solves;
  } else {
    problem.solve(foot);
  }
  const fem::ContactSolveReport& report = problem.report();
  for (unsigned int d = 0; d < 3; ++d) {
    result.foot_translation[d] = foot.translation[d];
    result.foot_rotation[d] = foot.rotation[d];
  }

  result.n_dofs = problem.n_dofs();
  result.n_cells = problem.n_cells();
  result.n_contact_nodes = problem.n_contact_nodes();
  result.n_ranks = dealii::Utilities::MPI::n_mpi_processes(communicator);
  result.iterations = report.iterations;
  result.residual = report.residual;
  result.n_separated = report.n_separated;
  result.n_stick = report.n_stick;
  result.n_slip = report.n_slip;
  result.foot_force = problem.foot_force();
  result.foot_moment = problem.foot_moment(foot.center);
  result.ground_force = problem.ground_force();
  result.max_pressure = problem.max_pressure();
  if (scene.output.write_vtu)
    write_fields(problem, output);
  const auto nodes = problem.gather_contact_nodes();
  if (dealii::Utilities::MPI::this_mpi_process(communicator) == 0)
    fem::write_file_atomically(output / "contact_nodes.csv", [&](std::ostream& os) {
      os.precision(12);
      os << "x,y,z,force_x,force_y,force_z,u_x,u_y,u_z,area,pressure,state\n";
      const char* states[] = {"separated", "stick", "slip"};
      for (const auto& node : nodes)
        os << node.position[0] << "," << node.position[1] << "," << node.position[2] << ","
           << node.force[0] << "," << node.force[1] << "," << node.force[2] << ","
           << node.displacement[0] << "," << node.displacement[1] << "," << node.displacement[2]
           << "," << node.area << "," << node.force[2] / node.area << ","
           << states[static_cast<int>(node.state)] << "\n";
    });
  dealii::Utilities::System::MemoryStats memory;
  dealii::Utilities::System::get_memory_stats(memory);
  double per_iteration = 0;
  for (const double t : report.iteration_times)
    per_iteration += t / std::max<std::size_t>(1, report.iteration_times.size());
  result.setup_time = gather(problem.setup_time(), communicator);
  result.assembly_time = gather(problem.assembly_time(), communicator);
  result.solve_time = gather(report.solve_time, communicator);
  result.mean_iteration_time = gather(per_iteration, communicator);
  result.peak_memory = gather(memory.VmHWM / 1024.0, communicator);
  result.wall_time =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return result;
}

std::string format_static_contact_summary(const StaticContactResult& r) {
  std::ostringstream os;
  os << "sole: " << r.n_cells << " cells, " << r.n_dofs << " dofs, " << r.n_contact_nodes
     << " contact nodes, " << r.n_ranks << " MPI rank(s)\n"
     << "semismooth Newton: " << r.iterations << " iterations, relative residual " << r.residual
     << "\n"
     << "contact nodes: " << r.n_separated << " separated, " << r.n_stick << " stick, " << r.n_slip
     << " slip\n"
     << "foot translation: " << r.foot_translation << " m, rotation: " << r.foot_rotation << " rad";
  if (r.load_iterations > 0)
    os << " (force control: " << r.load_iterations << " quasi-Newton iterations, "
       << r.contact_solves << " contact solves)";
  os << "\n"
     << "force of the foot on the sole: " << r.foot_force << " N\n"
     << "moment of the foot about the rotation point: " << r.foot_moment << " N m\n"
     << "sum of the ground's nodal forces: " << r.ground_force << " N\n"
     << "maximum contact pressure: " << r.max_pressure << " Pa\n";
  for (unsigned int rank = 0; rank < r.peak_memory.size(); ++rank)
    os << "rank " << rank << ": setup " << r.setup_time[rank] << " s, assembly "
       << r.assembly_time[rank] << " s, solve " << r.solve_time[rank] << " s ("
       << r.mean_iteration_time[rank] << " s per iteration), peak memory " << r.peak_memory[rank]
       << " MB\n";
  os << "wall time: " << r.wall_time << " s\n";
  return os.str();
}

std::string static_contact_csv(const StaticContactResult& r) {
  std::ostringstream os;
  os.precision(12);
  os << "name,value\n"
     << "dofs," << r.n_dofs << "\ncells," << r.n_cells << "\ncontact_nodes," << r.n_contact_nodes
     << "\nranks," << r.n_ranks << "\niterations," << r.iterations << "\nresidual," << r.residual
     << "\nseparated," << r.n_separated << "\nstick," << r.n_stick << "\nslip," << r.n_slip;
  const char* axes = "xyz";
  for (unsigned int d = 0; d < 3; ++d)
    os << "\nfoot_force_" << axes[d] << "," << r.foot_force[d];
  for (unsigned int d = 0; d < 3; ++d)
    os << "\nfoot_moment_" << axes[d] << "," << r.foot_moment[d];
  for (unsigned int d = 0; d < 3; ++d)
    os << "\nground_force_" << axes[d] << "," << r.ground_force[d];
  os << "\nmax_pressure," << r.max_pressure;
  for (unsigned int d = 0; d < 3; ++d)
    os << "\nfoot_translation_" << axes[d] << "," << r.foot_translation[d];
  for (unsigned int d = 0; d < 3; ++d)
    os << "\nfoot_rotation_" << axes[d] << "," << r.foot_rotation[d];
  os << "\nload_iterations," << r.load_iterations << "\ncontact_solves," << r.contact_solves;
  for (unsigned int rank = 0; rank < r.peak_memory.size(); ++rank)
    os << "\nsetup_time_" << rank << "," << r.setup_time[rank] << "\nassembly_time_" << rank << ","
       << r.assembly_time[rank] << "\nsolve_time_" << rank << "," << r.solve_time[rank]
       << "\niteration_time_" << rank << "," << r.mean_iteration_time[rank] << "\npeak_memory_mb_"
       << rank << "," << r.peak_memory[rank];
  os << "\nwall_time," << r.wall_time << "\n";
  return os.str();
}

} // namespace plantar::app
