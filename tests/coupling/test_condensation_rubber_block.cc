// Bonded rubber block (validation.md, Gent-Lindley): apparent compression
// modulus E_a = (F/A) / (delta / t) of the condensed sole, top face attached
// (u = 0), the contact face loaded either
//   - by a rigid plate: u_z = delta on every contact node (the setting of the
//     Gent-Lindley formula), or
//   - by a uniform pressure (consistent nodal forces f; delta = f . u / F, the
//     area average of u_z),
// with the contact nodes
//   - laterally FREE (frictionless ground: only normal forces, u_c = C f), or
//   - laterally FIXED (sticking ground: u_t = 0 imposed by the Schur
//     complement of the tangential block on the 3 n_c system:
//     u_n = (C_nn - C_nt C_tt^-1 C_tn) f_n), cross-checked against the same
//     constraint written with K_c = C^-1: u_n = (K_c)_nn^-1 f_n.
//
// References (validation.md), block 0.23 x 0.13 x 0.021 m, S = L W / (2 t (L + W)):
//   1/E_a = 1/(E (1 + 2 S^2)) + 1/K     (both faces bonded; frictionless bottom:
//   S/2, exact by the mid-plane symmetry of a block of thickness 2 t).
// For nu = 0.3 the discrete bounds are rigorous: E <= E_a(frictionless) <=
// E_a(bonded) <= M = E (1 - nu)/((1 + nu)(1 - 2 nu)) = 1.346 E (the uniaxial and
// the laterally confined fields lie in the FE space, and every added constraint
// stiffens). For nu -> 0.5 Gent-Lindley is an approximate theory (it assumes a
// parabolic bulge and ignores the edge zones): tolerances are justified at the
// test. Q2 is used (P1/Q1 lock).
#include "condensation_test_utilities.h"

#include <Eigen/Cholesky>
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>
#include <utility>
#include <vector>

namespace plantar::coupling {
namespace {

constexpr double length = 0.23, width = 0.13, thickness = 0.021, youngs_modulus = 1e6;
constexpr double pressure = 1e4; // Pa (the result is linear in it)

struct BlockResult {
  // E_a / E under a uniform pressure (flexible loading) ...
  double frictionless, bonded, bonded_via_stiffness;
  // ... and under a rigid plate (uniform normal displacement of all contact nodes).
  double plate_frictionless, plate_bonded;
};

BlockResult apparent_moduli(double poisson_ratio, unsigned int degree, unsigned int n_x,
                            unsigned int n_y, unsigned int n_z) {
  dealii::Triangulation<3> tria;
  testing::make_sole_box(tria, fem::CellKind::hexahedron, n_x, n_y, n_z, length, width, thickness);
  const fem::MaterialTable materials(fem::LinearElasticMaterial(youngs_modulus, poisson_ratio));
  CondensationParameters parameters;
  parameters.degree = degree;
  parameters.compute_stiffness = true;
  const CondensedSole sole(tria, materials, parameters);
  const int n_c = sole.n_contacts();
  Eigen::VectorXd forces(3 * n_c);
  sole.contact_load(Eigen::Vector3d(0, 0, pressure), forces); // ground pushes up (+z)
  const double total_force = pressure * length * width;
  const auto modulus = [&](double mean_deflection) {
    return pressure / (mean_deflection / thickness) / youngs_modulus;
  };
  BlockResult result{};
  // Frictionless: only normal forces. Displacement is +z (towards the top).
  const Eigen::VectorXd u = sole.compliance() * forces;
  result.frictionless = modulus(forces.dot(u) / total_force);

  // Sticking: u_t = 0 by the Schur complement of C_tt.
  std::vector<int> normal(n_c), tangent(2 * n_c);
  for (int k = 0; k < n_c; ++k) {
    normal[k] = 3 * k + 2;
    tangent[2 * k] = 3 * k;
    tangent[2 * k + 1] = 3 * k + 1;
  }
  const Eigen::MatrixXd& c = sole.compliance();
  const Eigen::VectorXd f_n = forces(normal);
  const Eigen::LLT<Eigen::MatrixXd> c_tt(c(tangent, tangent));
  const Eigen::VectorXd f_t = -c_tt.solve(c(tangent, normal) * f_n); // friction forces
  const Eigen::VectorXd u_n = c(normal, normal) * f_n + c(normal, tangent) * f_t;
  result.bonded = modulus(f_n.dot(u_n) / total_force);
  const Eigen::MatrixXd& k_c = sole.stiffness();
  const Eigen::VectorXd u_n_stiffness = k_c(normal, normal).llt().solve(f_n);
  result.bonded_via_stiffness = modulus(f_n.dot(u_n_stiffness) / total_force);
  // Rigid plate: u_n = delta for every node. Frictionless (f_t = 0): u_n = C_nn f_n;
  // bonded (u_t = 0): u_n = S f_n with S = C_nn - C_nt C_tt^-1 C_tn.
  const double delta = 1e-4; // m
  const Eigen::VectorXd plate = Eigen::VectorXd::Constant(n_c, delta);
  const Eigen::MatrixXd schur =
      c(normal, normal) - c(normal, tangent) * c_tt.solve(c(tangent, normal));
  const double plate_frictionless_force = c(normal, normal).llt().solve(plate).sum();
  const double plate_bonded_force = schur.llt().solve(plate).sum();
  const double area = length * width;
  result.plate_frictionless =
      plate_frictionless_force / area / (delta / thickness) / youngs_modulus;
  result.plate_bonded = plate_bonded_force / area / (delta / thickness) / youngs_modulus;
  // The tangential displacement under f_t must vanish (to round-off).
  Eigen::VectorXd f_full(3 * n_c);
  for (int k = 0; k < n_c; ++k)
    f_full.segment<3>(3 * k) << f_t(2 * k), f_t(2 * k + 1), f_n(k);
  const Eigen::VectorXd u_full = c * f_full;
  double max_tangential = 0, max_normal = 0;
  for (int k = 0; k < n_c; ++k) {
    max_tangential = std::max(max_tangential, u_full.segment<2>(3 * k).cwiseAbs().maxCoeff());
    max_normal = std::max(max_normal, std::abs(u_full(3 * k + 2)));
  }
  EXPECT_LT(max_tangential, 1e-10 * max_normal);
  return result;
}

double gent_lindley(double poisson_ratio, double shape_factor) {
  const double bulk = youngs_modulus / (3 * (1 - 2 * poisson_ratio));
  return 1.0 / (1.0 / (youngs_modulus * (1 + 2 * shape_factor * shape_factor)) + 1.0 / bulk) /
         youngs_modulus;
}

TEST(RubberBlock, CompressibleBoundsNu03) {
  const double nu = 0.3;
  const double confined = (1 - nu) / ((1 + nu) * (1 - 2 * nu));
  const BlockResult r = apparent_moduli(nu, 2, 8, 4, 2);
  std::printf("\nnu = 0.3, Q2 8x4x2, uniform pressure: E_a/E frictionless %.4f, bonded %.4f (via "
              "K_c %.4f); "
              "bounds 1 <= . <= M/E = %.4f\n",
              r.frictionless, r.bonded, r.bonded_via_stiffness, confined);
  std::printf("nu = 0.3, rigid plate: E_a/E frictionless %.4f, bonded %.4f\n", r.plate_frictionless,
              r.plate_bonded);
  EXPECT_GT(r.frictionless, 1.0);
  EXPECT_GT(r.bonded, r.frictionless);
  EXPECT_LT(r.bonded, confined);
  EXPECT_GT(r.plate_frictionless, 1.0);
  EXPECT_GT(r.plate_bonded, r.plate_frictionless);
  EXPECT_LT(r.plate_bonded, confined);
  EXPECT_NEAR(r.bonded_via_stiffness, r.bonded, 1e-9 * r.bonded);
}

// Prints one row per mesh and returns the result.
BlockResult gent_lindley_row(double nu, unsigned int n_x, unsigned int n_y, unsigned int n_z) {
  const double shape = length * width / (2 * thickness * (length + width));
  const BlockResult r = apparent_moduli(nu, 2, n_x, n_y, n_z);
  const double frictionless_ref = gent_lindley(nu, shape / 2), bonded_ref = gent_lindley(nu, shape);
  const std::string mesh =
      "Q2 " + std::to_string(n_x) + "x" + std::to_string(n_y) + "x" + std::to_string(n_z);
  std::printf("%7.4f %11s | %8.3f %8.3f %+6.1f%% | %8.3f %8.3f %+6.1f%% | %8.3f %8.3f | %.1e\n", nu,
              mesh.c_str(), r.plate_frictionless, frictionless_ref,
              100 * (r.plate_frictionless / frictionless_ref - 1), r.plate_bonded, bonded_ref,
              100 * (r.plate_bonded / bonded_ref - 1), r.frictionless, r.bonded,
              std::abs(r.bonded_via_stiffness / r.bonded - 1));
  EXPECT_NEAR(r.bonded_via_stiffness, r.bonded, 1e-6 * r.bonded); // K_c = C^-1: cond(C) eps
  EXPECT_GT(r.plate_bonded, 1.5 * r.plate_frictionless) << "sticking must stiffen markedly";
  EXPECT_GT(r.bonded, 1.5 * r.frictionless) << "sticking must stiffen markedly";
  return r;
}

void print_header() {
  const double shape = length * width / (2 * thickness * (length + width));
  std::printf("\nblock %.3f x %.3f x %.3f m, S = %.3f; E_a / E; formula 1/E_a = 1/(E(1+2S^2)) + "
              "1/K (frictionless bottom: S/2)\n",
              length, width, thickness, shape);
  std::printf("%7s %11s | %-24s | %-24s | %-17s | %s\n", "", "", "rigid plate, frictionless",
              "rigid plate, bonded", "uniform pressure", "");
  std::printf("%7s %11s | %8s %8s %7s | %8s %8s %7s | %8s %8s | %s\n", "nu", "mesh", "FEM",
              "formula", "dev", "FEM", "formula", "dev", "frictnl", "bonded", "K_c check");
}

// Tolerances. The displacement FEM over-estimates the exact E_a (it is an
// upper bound, decreasing under refinement: MeshConvergence, where nu = 0.49
// moves by 2 % from 8x4x2 to 16x8x4). Gent-Lindley is itself approximate
// (about 5-20 %, worst at the low shape factor S/2 of the frictionless case).
// nu = 0.49 (asserted): rigid-plate bonded within [-5 %, +10 %] of the
// formula, frictionless within [-5 %, +25 %]. nu = 0.4999: Q2 still locks
// volumetrically on these meshes (+38 % at 8x4x2, +14 % at 16x8x4): only
// printed, and checked to lie above the formula (upper bound) and above nu = 0.49.
// A uniform pressure is a weaker (more flexible) loading than a rigid plate of
// the same mean deflection, so its E_a must be lower.
TEST(RubberBlock, NearlyIncompressibleGentLindley) {
  print_header();
  const double shape = length * width / (2 * thickness * (length + width));
  const BlockResult r49 = gent_lindley_row(0.49, 8, 4, 2);
  const BlockResult r4999 = gent_lindley_row(0.4999, 8, 4, 2);
  const double bonded_dev = r49.plate_bonded / gent_lindley(0.49, shape) - 1;
  const double frictionless_dev = r49.plate_frictionless / gent_lindley(0.49, shape / 2) - 1;
  EXPECT_GT(bonded_dev, -0.05);
  EXPECT_LT(bonded_dev, 0.10);
  EXPECT_GT(frictionless_dev, -0.05);
  EXPECT_LT(frictionless_dev, 0.25);
  EXPECT_GT(r4999.plate_bonded, gent_lindley(0.4999, shape));
  EXPECT_GT(r4999.plate_bonded, r49.plate_bonded);
  for (const BlockResult& r : {r49, r4999}) {
    EXPECT_LT(r.frictionless, r.plate_frictionless);
    EXPECT_LT(r.bonded, r.plate_bonded);
  }
  std::printf("sticking / sliding stiffness ratio (rigid plate): nu 0.49 %.2f (formula %.2f), "
              "nu 0.4999 %.2f (formula %.2f)\n",
              r49.plate_bonded / r49.plate_frictionless,
              gent_lindley(0.49, shape) / gent_lindley(0.49, shape / 2),
              r4999.plate_bonded / r4999.plate_frictionless,
              gent_lindley(0.4999, shape) / gent_lindley(0.4999, shape / 2));
}

// Refinement study (slow) on nested meshes: the displacement FEM bounds the
// exact E_a from above and decreases under nested refinement.
TEST(RubberBlock, MeshConvergence) {
  print_header();
  for (const double nu : {0.49, 0.4999}) {
    BlockResult previous{1e300, 1e300, 1e300, 1e300, 1e300};
    const unsigned int meshes[][3] = {{8, 4, 1}, {8, 4, 2}, {16, 8, 2}, {16, 8, 4}};
    for (const auto& m : meshes) {
      const BlockResult r = gent_lindley_row(nu, m[0], m[1], m[2]);
      EXPECT_LE(r.plate_bonded, previous.plate_bonded * (1 + 1e-9));
      EXPECT_LE(r.plate_frictionless, previous.plate_frictionless * (1 + 1e-9));
      EXPECT_LE(r.bonded, previous.bonded * (1 + 1e-9));
      EXPECT_LE(r.frictionless, previous.frictionless * (1 + 1e-9));
      previous = r;
    }
  }
}

} // namespace
} // namespace plantar::coupling
