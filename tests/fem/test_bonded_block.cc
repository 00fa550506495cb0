// Bonded block in compression (validation.md, "Bonded rubber block"):
// block 0.23 x 0.13 x 0.021 m, bottom face fixed, top face bonded to a rigid
// plate pushed down by delta. Apparent modulus E_a = (F / A) / (delta / t),
// F the reaction on the plate.
//   nu = 0:     E_a = E exactly (no lateral expansion).
//   nu = 0.3:   E < E_a < M = E (1 - nu) / ((1 + nu)(1 - 2 nu)) (constrained modulus).
//   nu = 0.45:  Gent-Lindley with finite bulk modulus K = E / (3 (1 - 2 nu)):
//               1 / E_a = 1 / (E (1 + 2 S^2)) + 1 / K,  S = L W / (2 t (L + W)).
// Then P1 tetrahedra against P2 as nu -> 0.5: volumetric locking measured.
#include "fem_test_utilities.h"

#include <gtest/gtest.h>

#include <cstdio>

namespace plantar::fem {
namespace {

constexpr double L = 0.23, W = 0.13, t = 0.021, E = 4e6, delta = 1e-5;

double shape_factor() {
  return L * W / (2 * t * (L + W));
}

double gent_lindley(double nu) {
  const double S = shape_factor(), K = E / (3 * (1 - 2 * nu));
  return 1.0 / (1.0 / (E * (1 + 2 * S * S)) + 1.0 / K);
}

double apparent_modulus(CellKind kind, unsigned int degree, double nu, unsigned int n_xy_per_t,
                        unsigned int n_z) {
  dealii::Triangulation<3> tria;
  const unsigned int n_x = static_cast<unsigned int>(std::round(L / t * n_xy_per_t));
  const unsigned int n_y = static_cast<unsigned int>(std::round(W / t * n_xy_per_t));
  testing::make_box(tria, kind, n_x, n_y, n_z, L, W, t);
  const MaterialTable materials(LinearElasticMaterial(E, nu));
  const Discretization disc(kind, degree);
  LinearElasticity problem(tria, disc, materials);
  const dealii::Functions::ConstantFunction<3> plate(std::vector<double>{0, 0, -delta});
  problem.setup({{4, nullptr}, {5, &plate}});
  problem.assemble();
  problem.solve();
  const double force = -problem.reaction_force(5)[2];
  return force / (L * W) / (delta / t);
}

TEST(BondedBlock, ApparentModulus) {
  std::printf("\nBonded block %.2f x %.2f x %.3f m, S = %.3f\n", L, W, t, shape_factor());
  // nu = 0: exact.
  const double e0 = apparent_modulus(CellKind::hexahedron, 1, 0.0, 1, 2);
  std::printf("nu = 0:    E_a / E = %.12f (exact 1)\n", e0 / E);
  EXPECT_NEAR(e0 / E, 1.0, 1e-10);

  // nu = 0.3: between E and the constrained modulus.
  const double nu = 0.3, M = E * (1 - nu) / ((1 + nu) * (1 - 2 * nu));
  const double e3 = apparent_modulus(CellKind::hexahedron, 2, nu, 2, 3);
  std::printf("nu = 0.3:  E_a / E = %.4f (bounds 1 .. %.4f)\n", e3 / E, M / E);
  EXPECT_GT(e3, E);
  EXPECT_LT(e3, M);

  // nu = 0.4, 0.45: Gent-Lindley with finite bulk modulus. The formula is an
  // approximate theory built for nu -> 0.5 (beta = 2 from the incompressible
  // parabolic bulge): the FE result, mesh-converged to 1 %, must approach it
  // as nu grows and agree within 15 % at nu = 0.45.
  const double e40 = apparent_modulus(CellKind::hexahedron, 2, 0.40, 2, 4);
  const double coarse = apparent_modulus(CellKind::hexahedron, 2, 0.45, 1, 2);
  const double e45 = apparent_modulus(CellKind::hexahedron, 2, 0.45, 2, 4);
  std::printf("nu = 0.40: E_a / E = %.4f (Q2), Gent-Lindley %.4f, difference %.1f %%\n", e40 / E,
              gent_lindley(0.4) / E, 100 * (e40 / gent_lindley(0.4) - 1));
  std::printf("nu = 0.45: E_a / E = %.4f (Q2 1 cell/t) %.4f (Q2 2 cells/t), Gent-Lindley %.4f, "
              "difference %.1f %%\n",
              coarse / E, e45 / E, gent_lindley(0.45) / E, 100 * (e45 / gent_lindley(0.45) - 1));
  EXPECT_NEAR(coarse / e45, 1.0, 0.01);
  EXPECT_NEAR(e45 / gent_lindley(0.45), 1.0, 0.15);
  EXPECT_LT(std::abs(e45 / gent_lindley(0.45) - 1), std::abs(e40 / gent_lindley(0.4) - 1));
}

TEST(BondedBlock, VolumetricLockingOfP1) {
  std::printf("\nVolumetric locking: E_a / E of P1 and P2 tetrahedra (same mesh, 2 cells per t)\n");
  std::printf("%8s %10s %10s %10s %14s\n", "nu", "P1", "P2", "P1/P2", "Gent-Lindley");
  double previous_ratio = 0;
  for (const double nu : {0.3, 0.45, 0.49, 0.499, 0.4999}) {
    const double p1 = apparent_modulus(CellKind::tetrahedron, 1, nu, 2, 2);
    const double p2 = apparent_modulus(CellKind::tetrahedron, 2, nu, 2, 2);
    std::printf("%8.4f %10.3f %10.3f %10.3f %14.3f\n", nu, p1 / E, p2 / E, p1 / p2,
                gent_lindley(nu) / E);
    // P1 is always stiffer than P2 on the same mesh, and increasingly so.
    EXPECT_GT(p1 / p2, previous_ratio);
    previous_ratio = p1 / p2;
  }
  EXPECT_GT(previous_ratio, 1.5) << "P1 at nu = 0.4999 is expected to lock";
}

} // namespace
} // namespace plantar::fem
