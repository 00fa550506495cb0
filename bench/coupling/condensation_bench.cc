// Precomputation cost of CondensedSole (coupling/condensed_sole.h) against the
// number of contact nodes: the HRP-2 sole of meshes/sole_box.geo (0.2172 x
// 0.138 x 0.02 m) meshed with Q1 hexahedra (gmsh transfinite, so n_c =
// (Ceil(L/h) + 1)(Ceil(W/h) + 1)) for decreasing mesh size h.
// Prints wall-clock seconds per stage and the memory kept. A timing app, not
// a test: it never passes or fails. Usage: condensation_bench [h1 h2 ...] (m).
#include "bench/coupling/sole_box_condensation.h"

#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <vector>

using namespace plantar;

namespace {

double megabytes(std::size_t bytes) {
  return static_cast<double>(bytes) / (1024.0 * 1024.0);
}

} // namespace

int main(int argc, char** argv) {
  std::vector<double> sizes = {0.02, 0.012, 0.008, 0.006, 0.005, 0.004};
  if (argc > 1) {
    sizes.clear();
    for (int i = 1; i < argc; ++i)
      sizes.push_back(std::atof(argv[i]));
  }
  std::printf("CondensedSole precomputation, HRP-2 sole Q1, E = 4 MPa, nu = 0.3, CHOLMOD "
              "supernodal, blocks of 64 right-hand sides, 1 thread\n");
  std::printf("%7s %6s %7s | %8s %8s %9s %8s %8s | %9s %8s %8s %8s %9s\n", "h (m)", "n_c", "dofs",
              "assembly", "factor", "3n_c solv", "K_nn fac", "total s", "K fac MB", "C MB",
              "K_nn MB", "sparse MB", "kept MB");
  for (const double h : sizes) {
    const auto sole = bench::condense_sole_box(h, 64);
    const auto& t = sole.timings();
    const auto& m = sole.memory();
    std::printf("%7.4f %6d %7d | %8.3f %8.3f %9.3f %8.3f %8.3f | %9.1f %8.1f %8.1f %8.1f %9.1f\n",
                h, sole.n_contacts(), sole.n_dofs(), t.assembly, t.factorization, t.contact_solves,
                t.recovery_factorization, t.total(), megabytes(m.condensation_factorization_bytes),
                megabytes(m.compliance_bytes), megabytes(m.recovery_factorization_bytes),
                megabytes(m.sparse_matrix_bytes), megabytes(m.total()));
    std::fflush(stdout);
  }
  // Effect of the block size on the 3 n_c solves (one right-hand side at a time vs blocks).
  const double h = 0.008;
  std::printf("\nBlock size of the 3 n_c solves, h = %.3f m\n%6s %10s\n", h, "block", "solves s");
  for (const int block : {1, 16, 64, 256}) {
    const auto sole = bench::condense_sole_box(h, block);
    std::printf("%6d %10.3f\n", block, sole.timings().contact_solves);
    std::fflush(stdout);
  }
  return 0;
}
