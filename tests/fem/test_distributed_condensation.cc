// The contact compliance built on several ranks (fem/distributed_condensation.h, issue 26), run
// under mpirun at 1 and 2 ranks: C = [K_D^-1]_cc from MUMPS on the distributed system equals the
// serial coupling::CondensedSole's C (CHOLMOD on the serial deal.II system, symmetrised) to
// 1e-10 relative in the max norm, Q1 and Q2, on a sole of two layers (interior dofs), with a
// block size that does not divide 3 n_c; each rank's rows and the gathered C alike.
#include "coupling/condensed_sole.h"
#include "fem/distributed_condensation.h"
#include "fem/distributed_contact.h"
#include "tests/fem/sole_box_grid.h"

#include <deal.II/base/mpi.h>
#include <deal.II/grid/grid_generator.h>

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <map>
#include <tuple>

namespace plantar::fem {
namespace {

using dealii::Point;

constexpr double length = 0.2172, width = 0.138, thickness = 0.02, E = 4e6, nu = 0.3;

bool rank0() {
  return dealii::Utilities::MPI::this_mpi_process(MPI_COMM_WORLD) == 0;
}

void make_sole(dealii::Triangulation<3>& tria, unsigned int refinements) {
  fem::test::make_sole_box(tria, 8, 6, 2, refinements);
}

std::tuple<long long, long long, long long> key(double x, double y, double z) {
  return {std::llround(x * 1e9), std::llround(y * 1e9), std::llround(z * 1e9)};
}

TEST(DistributedCondensation, EqualsSerialCondensedSole) {
  const MaterialTable materials{LinearElasticMaterial(E, nu)};
  // Q1 refined once and Q2 unrefined: 221 contact nodes each, 3315 dofs.
  for (const auto& [degree, refinements] : {std::pair{1u, 1u}, std::pair{2u, 0u}}) {
    dealii::Triangulation<3> coarse;
    make_sole(coarse, 0);
    DistributedContactSettings settings;
    settings.degree = degree;
    settings.refinements = refinements;
    const DistributedContact problem(MPI_COMM_WORLD, coarse, materials, settings);
    DistributedCondensationSettings condensation_settings;
    condensation_settings.block_size = 100; // 3 n_c = 663: a last block of 63
    const DistributedCondensation condensed(problem, condensation_settings);

    dealii::Triangulation<3> tria;
    make_sole(tria, refinements);
    coupling::CondensationParameters parameters;
    parameters.degree = degree;
    const coupling::CondensedSole serial(tria, materials, parameters);
    const int n_c = serial.n_contacts();
    ASSERT_EQ(static_cast<unsigned int>(n_c), condensed.n_contact_nodes());
    const std::size_t n = 3 * static_cast<std::size_t>(n_c);

    // The serial C in the distributed order (by position).
    std::map<std::tuple<long long, long long, long long>, int> serial_index;
    const auto& x = serial.contact_positions();
    for (int k = 0; k < n_c; ++k)
      serial_index[key(x(k, 0), x(k, 1), x(k, 2))] = k;
    std::vector<int> to_serial(n_c);
    for (int k = 0; k < n_c; ++k) {
      const Point<3>& p = condensed.contact_positions()[k];
      const auto found = serial_index.find(key(p[0], p[1], p[2]));
      ASSERT_NE(found, serial_index.end()) << "contact node at " << p << " not in the serial sole";
      to_serial[k] = found->second;
    }
    const auto reference = [&](std::size_t i, std::size_t j) {
      return serial.compliance()(3 * to_serial[i / 3] + i % 3, 3 * to_serial[j / 3] + j % 3);
    };
    const double largest = serial.compliance().cwiseAbs().maxCoeff();

    // Each rank's rows.
    const auto& rows = condensed.local_rows();
    double local_difference = 0;
    for (std::size_t r = 0; r < rows.size(); ++r)
      for (std::size_t j = 0; j < n; ++j)
        local_difference =
            std::max(local_difference,
                     std::abs(condensed.local_compliance()[r * n + j] - reference(rows[r], j)));
    const double rows_difference =
        dealii::Utilities::MPI::max(local_difference, MPI_COMM_WORLD) / largest;
    const unsigned int n_rows =
        dealii::Utilities::MPI::sum(static_cast<unsigned int>(rows.size()), MPI_COMM_WORLD);
    const unsigned int fewest_rows =
        dealii::Utilities::MPI::min(static_cast<unsigned int>(rows.size()), MPI_COMM_WORLD);
    EXPECT_EQ(n_rows, n);
    EXPECT_LT(rows_difference, 1e-10);

    // The gathered C.
    const std::vector<double> gathered = condensed.gather(0);
    if (rank0()) {
      ASSERT_EQ(gathered.size(), n * n);
      double difference = 0, asymmetry = 0;
      for (std::size_t i = 0; i < n; ++i)
        for (std::size_t j = 0; j < n; ++j) {
          difference = std::max(difference, std::abs(gathered[i * n + j] - reference(i, j)));
          asymmetry = std::max(asymmetry, std::abs(gathered[i * n + j] - gathered[j * n + i]));
        }
      std::printf("Q%u, %u dofs, %d contact nodes, %u ranks (fewest rows on a rank: %u): max |C - "
                  "C_serial| / max |C_serial| = %.2e (rows on each rank: %.2e), asymmetry %.1e, "
                  "max |C| = %.6e m/N; factor %.0f MB (all ranks), %.3f s + solves %.3f s\n",
                  degree, static_cast<unsigned int>(problem.n_dofs()), n_c,
                  dealii::Utilities::MPI::n_mpi_processes(MPI_COMM_WORLD), fewest_rows,
                  difference / largest, rows_difference, asymmetry / largest, largest,
                  condensed.factor_megabytes_total(), condensed.timings().factorization,
                  condensed.timings().contact_solves);
      EXPECT_LT(difference / largest, 1e-10);
      EXPECT_LT(asymmetry / largest, 1e-10);
      EXPECT_GT(largest, 1e-9); // about h / (E A): not a zero operator
    } else {
      EXPECT_TRUE(gathered.empty());
    }
  }
}

TEST(DistributedCondensation, RefusesBadBlockSize) {
  const MaterialTable materials{LinearElasticMaterial(E, nu)};
  dealii::Triangulation<3> coarse;
  make_sole(coarse, 0);
  const DistributedContact problem(MPI_COMM_WORLD, coarse, materials, {});
  DistributedCondensationSettings settings;
  settings.block_size = 0;
  try {
    DistributedCondensation condensed(problem, settings);
    ADD_FAILURE() << "block size 0 accepted";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("block size = 0"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("[1, 4096]"), std::string::npos) << e.what();
  }
}

} // namespace
} // namespace plantar::fem

int main(int argc, char** argv) {
  dealii::Utilities::MPI::MPI_InitFinalize mpi(argc, argv, 1);
  ::testing::InitGoogleTest(&argc, argv);
  if (dealii::Utilities::MPI::this_mpi_process(MPI_COMM_WORLD) != 0) {
    auto& listeners = ::testing::UnitTest::GetInstance()->listeners();
    delete listeners.Release(listeners.default_result_printer());
  }
  return RUN_ALL_TESTS();
}
