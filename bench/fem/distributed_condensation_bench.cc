// The contact compliance built on several ranks (fem/distributed_condensation.h, issue 26): time
// and memory of one condensation against the DoF, run under mpirun at any rank count. Prints one
// CSV line (header first); never passes or fails (bench/README.md). The sole of
// scenes/static_contact.prm: the box 0.2172 x 0.138 x 0.02 m in 11 x 7 x 1 Q1 hexahedra refined
// r times, top attached, bottom in contact. With --serial (one rank), also condenses the same
// mesh serially (coupling::CondensedSole, CHOLMOD) after the measurement and prints the max
// relative difference of the two C.
//   mpirun -np R distributed_condensation_bench REFINEMENTS [BLOCK_SIZE (128)] [--serial]
#include "bench/fem/peak_memory.h"
#include "coupling/condensed_sole.h"
#include "fem/distributed_condensation.h"
#include "fem/distributed_contact.h"
#include "tests/fem/sole_box_grid.h"

#include <deal.II/base/mpi.h>
#include <deal.II/grid/grid_generator.h>

#include <sys/resource.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <map>
#include <tuple>

using namespace plantar;
using dealii::Point;

namespace {

void make_sole(dealii::Triangulation<3>& tria, unsigned int refinements) {
  fem::test::make_sole_box(tria, 11, 7, 1, refinements);
}

double since(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

} // namespace

int main(int argc, char** argv) {
  dealii::Utilities::MPI::MPI_InitFinalize mpi(argc, argv, 1);
  const MPI_Comm comm = MPI_COMM_WORLD;
  const bool root = dealii::Utilities::MPI::this_mpi_process(comm) == 0;
  const unsigned int ranks = dealii::Utilities::MPI::n_mpi_processes(comm);
  if (argc < 2) {
    if (root)
      std::fprintf(stderr, "usage: distributed_condensation_bench REFINEMENTS [BLOCK_SIZE] "
                           "[--serial]\n");
    return 2;
  }
  const unsigned int refinements = std::atoi(argv[1]);
  fem::DistributedCondensationSettings settings;
  bool serial = false;
  for (int i = 2; i < argc; ++i)
    if (std::strcmp(argv[i], "--serial") == 0)
      serial = true;
    else
      settings.block_size = std::atoi(argv[i]);
  const fem::MaterialTable materials{fem::LinearElasticMaterial(4e6, 0.3)};
  dealii::Triangulation<3> coarse;
  make_sole(coarse, 0);
  fem::DistributedContactSettings contact_settings;
  contact_settings.refinements = refinements;
  const auto start = std::chrono::steady_clock::now();
  const fem::DistributedContact problem(comm, coarse, materials, contact_settings);
  const fem::DistributedCondensation condensed(problem, settings);
  const double wall = since(start);
  const double setup = dealii::Utilities::MPI::max(problem.setup_time(), comm);
  const double assembly = dealii::Utilities::MPI::max(problem.assembly_time(), comm);
  const double factorization = dealii::Utilities::MPI::max(condensed.timings().factorization, comm);
  const double solves = dealii::Utilities::MPI::max(condensed.timings().contact_solves, comm);
  const double memory = dealii::Utilities::MPI::max(bench::peak_megabytes(), comm);
  const double factor_rank = dealii::Utilities::MPI::max(condensed.factor_megabytes_rank(), comm);
  const std::size_t n = 3 * condensed.n_contact_nodes();
  const double c_rank_mb =
      dealii::Utilities::MPI::max(condensed.local_compliance().size() * 8.0 / 1e6, comm);
  if (root) {
    std::printf("refinements,ranks,dofs,contact_nodes,block_size,setup_s,assembly_s,"
                "factorization_s,solves_s,wall_s,peak_mb_rank,factor_mb_total,factor_mb_rank,"
                "c_mb_rank\n");
    std::printf("%u,%u,%u,%u,%u,%.4g,%.4g,%.4g,%.4g,%.4g,%.0f,%.0f,%.0f,%.0f\n", refinements, ranks,
                static_cast<unsigned int>(problem.n_dofs()), condensed.n_contact_nodes(),
                settings.block_size, setup, assembly, factorization, solves, wall, memory,
                condensed.factor_megabytes_total(), factor_rank, c_rank_mb);
    std::fflush(stdout);
  }
  if (!serial || ranks != 1)
    return 0;
  const std::vector<double> c = condensed.gather(0);
  {
    dealii::Triangulation<3> tria;
    make_sole(tria, refinements);
    const auto serial_start = std::chrono::steady_clock::now();
    const coupling::CondensedSole sole(tria, materials, coupling::CondensationParameters{});
    const double serial_time = since(serial_start);
    std::map<std::tuple<long long, long long, long long>, int> index;
    const auto& x = sole.contact_positions();
    const auto key = [](double a, double b, double c3) {
      return std::make_tuple(std::llround(a * 1e9), std::llround(b * 1e9), std::llround(c3 * 1e9));
    };
    for (int k = 0; k < sole.n_contacts(); ++k)
      index[key(x(k, 0), x(k, 1), x(k, 2))] = k;
    std::vector<int> to_serial(condensed.n_contact_nodes());
    for (unsigned int k = 0; k < condensed.n_contact_nodes(); ++k) {
      const auto& p = condensed.contact_positions()[k];
      to_serial[k] = index.at(key(p[0], p[1], p[2]));
    }
    double difference = 0;
    for (std::size_t i = 0; i < n; ++i)
      for (std::size_t j = 0; j < n; ++j)
        difference = std::max(
            difference, std::abs(c[i * n + j] - sole.compliance()(3 * to_serial[i / 3] + i % 3,
                                                                  3 * to_serial[j / 3] + j % 3)));
    std::printf("serial CondensedSole (CHOLMOD): %.4g s (assembly %.3g, factorisation %.3g, "
                "solves %.3g); max |C - C_serial| / max |C_serial| = %.2e\n",
                serial_time, sole.timings().assembly, sole.timings().factorization,
                sole.timings().contact_solves,
                difference / sole.compliance().cwiseAbs().maxCoeff());
  }
  return 0;
}
