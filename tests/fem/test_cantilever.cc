// Cantilever under an end shear load against Timoshenko beam theory
// (validation.md): delta = P L^3 / (3 E I) + P L / (k G A), k = 5/6.
// Beam 10 x 1 x 1 m, clamped at x = 0, shear traction P / A on x = L.
// P2 and Q2 must be within 1 %; P1 tetrahedra lock in bending (shear
// locking): their deflection is printed and shown to be too small.
#include "fem_test_utilities.h"

#include <deal.II/numerics/vector_tools.h>
#include <gtest/gtest.h>

#include <cstdio>

namespace plantar::fem {
namespace {

constexpr double length = 10, height = 1, width = 1, E = 1e7, nu = 0.3, P = 1e3;

double timoshenko() {
  const double I = width * height * height * height / 12, A = width * height;
  const double G = E / (2 * (1 + nu)), k = 5.0 / 6.0;
  return P * length * length * length / (3 * E * I) + P * length / (k * G * A);
}

double tip_deflection(CellKind kind, unsigned int degree, unsigned int n_x, unsigned int n_yz) {
  dealii::Triangulation<3> tria;
  testing::make_box(tria, kind, n_x, n_yz, n_yz, length, width, height);
  const MaterialTable materials(LinearElasticMaterial(E, nu));
  const Discretization disc(kind, degree);
  LinearElasticity problem(tria, disc, materials);
  problem.setup({{0, nullptr}});
  problem.assemble();
  problem.add_traction(1, dealii::Tensor<1, 3>({0, 0, -P / (width * height)}));
  problem.solve();
  const dealii::Point<3> tip(length, width / 2, height / 2);
  dealii::Vector<double> value(3);
  dealii::VectorTools::point_value(*disc.mapping, problem.dof_handler(), problem.solution(), tip,
                                   value);
  return -value[2];
}

TEST(Cantilever, TimoshenkoP2Q2AndP1Locking) {
  const double reference = timoshenko();
  struct Case {
    CellKind kind;
    unsigned int degree, n_x, n_yz;
  };
  const Case cases[] = {{CellKind::tetrahedron, 1, 20, 2}, {CellKind::tetrahedron, 1, 40, 4},
                        {CellKind::tetrahedron, 2, 20, 2}, {CellKind::tetrahedron, 2, 40, 4},
                        {CellKind::hexahedron, 1, 20, 2},  {CellKind::hexahedron, 2, 20, 2},
                        {CellKind::hexahedron, 2, 40, 4}};
  std::printf("\nCantilever 10 x 1 x 1 m, Timoshenko tip deflection %.6e m\n", reference);
  std::printf("%4s %8s %14s %10s\n", "el", "mesh", "tip (m)", "ratio");
  for (const auto& c : cases) {
    const double tip = tip_deflection(c.kind, c.degree, c.n_x, c.n_yz);
    const double ratio = tip / reference;
    std::printf("%4s %3ux%ux%u %14.6e %10.4f\n", Discretization(c.kind, c.degree).name().c_str(),
                c.n_x, c.n_yz, c.n_yz, tip, ratio);
    if (c.degree == 2 && c.n_x == 40) {
      EXPECT_NEAR(ratio, 1.0, 0.01);
    } else if (c.degree == 1 && c.kind == CellKind::tetrahedron) {
      EXPECT_LT(ratio, 0.9) << "P1 tetrahedra are expected to lock in bending";
    }
  }
}

} // namespace
} // namespace plantar::fem
