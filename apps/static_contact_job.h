#pragma once
// The "static contact" scene (issue 26): the sole of subsection Sole (hexahedra, refined
// Static contact/Refinements times) attached to a rigid foot with a prescribed small rigid
// displacement, pressed onto the ground with Coulomb friction, solved on distributed PETSc
// (fem/distributed_contact.h) over the ranks of an MPI communicator. Writes contact.pvtu (one
// .vtu piece per rank), summary.txt, parameters.prm and summary.csv (last: it marks a
// finished run).

#include "apps/scene.h"

#include <deal.II/base/tensor.h>

#include <mpi.h>

#include <filesystem>
#include <string>
#include <vector>

namespace plantar::app {

struct StaticContactResult {
  unsigned long long n_dofs = 0;
  unsigned int n_cells = 0, n_contact_nodes = 0, n_ranks = 1;
  unsigned int iterations = 0;
  double residual = 0; ///< relative complementarity residual at the end
  unsigned int n_separated = 0, n_stick = 0, n_slip = 0;
  dealii::Tensor<1, 3> foot_force;                      ///< N, of the foot on the sole
  dealii::Tensor<1, 3> foot_moment;                     ///< N m, about the rotation point
  dealii::Tensor<1, 3> ground_force;                    ///< N, sum of the contact nodes' forces
  double max_pressure = 0;                              ///< Pa, largest nodal contact pressure
  dealii::Tensor<1, 3> foot_translation;                ///< m, prescribed or (force control) found
  dealii::Tensor<1, 3> foot_rotation;                   ///< rad
  unsigned int load_iterations = 0, contact_solves = 0; ///< force control
  /// Per rank (index = rank): s of wall time, MB of peak resident memory.
  std::vector<double> setup_time, assembly_time, solve_time, mean_iteration_time, peak_memory;
  double wall_time = 0; ///< s, whole job (rank 0)
};

/// Runs the scene on @p communicator (every rank calls it with the same scene) and writes the
/// fields into @p output (which rank 0 has created). Throws std::runtime_error (the same
/// message on every rank) on bad input or a numerical failure.
StaticContactResult run_static_contact(const Scene& scene, const std::filesystem::path& output,
                                       MPI_Comm communicator);

/// The summary's figures as text (summary.txt) and as name,value lines (summary.csv).
std::string format_static_contact_summary(const StaticContactResult& result);
std::string static_contact_csv(const StaticContactResult& result);

} // namespace plantar::app
