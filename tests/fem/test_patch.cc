// Patch test (MacNeal & Harder 1985): unit cube with distorted interior
// nodes, E = 1e6 Pa, nu = 0.25, boundary displacement
//   u = 1e-3 (2x + y + z, x + 2y + z, x + y + 2z) / 2  (m);
// exact strains eps_ii = 1e-3, gamma_ij = 1e-3, stresses sigma_ii = 2000 Pa,
// tau_ij = 400 Pa, reproduced to round-off by every element.
#include "fem_test_utilities.h"

#include <deal.II/base/function.h>
#include <deal.II/fe/fe_values.h>
#include <deal.II/grid/grid_tools.h>
#include <deal.II/numerics/vector_tools.h>
#include <gtest/gtest.h>

#include <cstdio>

namespace plantar::fem {
namespace {

class PatchField : public dealii::Function<3> {
public:
  PatchField() : dealii::Function<3>(3) {}
  double value(const dealii::Point<3>& p, unsigned int c) const override {
    const double sum = p[0] + p[1] + p[2];
    return 1e-3 * (sum + p[c]) / 2;
  }
};

void run_patch(CellKind kind, unsigned int degree) {
  dealii::Triangulation<3> tria;
  testing::make_box(tria, kind, 3, 3, 3, 1, 1, 1);
  dealii::GridTools::distort_random(0.25, tria, true, 42);
  const MaterialTable materials(LinearElasticMaterial(1e6, 0.25));
  const Discretization disc(kind, degree);
  LinearElasticity problem(tria, disc, materials);
  const PatchField exact;
  std::map<dealii::types::boundary_id, const dealii::Function<3>*> dirichlet;
  for (dealii::types::boundary_id b = 0; b < 6; ++b)
    dirichlet[b] = &exact;
  problem.setup(dirichlet);
  problem.assemble();
  problem.solve();

  // Nodal values.
  double max_u_error = 0;
  dealii::Vector<double> interpolated(problem.dof_handler().n_dofs());
  dealii::VectorTools::interpolate(*disc.mapping, problem.dof_handler(), exact, interpolated);
  for (unsigned int i = 0; i < interpolated.size(); ++i)
    max_u_error = std::max(max_u_error, std::abs(interpolated[i] - problem.solution()[i]));

  // Strains and stresses at every quadrature point.
  dealii::FEValues<3> fe_values(*disc.mapping, *disc.fe, disc.cell_quadrature,
                                dealii::update_gradients);
  const dealii::FEValuesExtractors::Vector u(0);
  std::vector<dealii::SymmetricTensor<2, 3>> strains(disc.cell_quadrature.size());
  double max_strain_error = 0, max_stress_error = 0;
  const auto& material = materials[0];
  for (const auto& cell : problem.dof_handler().active_cell_iterators()) {
    fe_values.reinit(cell);
    fe_values[u].get_function_symmetric_gradients(problem.solution(), strains);
    for (const auto& eps : strains) {
      const auto sigma = material.stress(eps);
      for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j) {
          const double eps_exact = (i == j) ? 1e-3 : 0.5e-3;
          const double sigma_exact = (i == j) ? 2000 : 400;
          max_strain_error = std::max(max_strain_error, std::abs(eps[i][j] - eps_exact));
          max_stress_error = std::max(max_stress_error, std::abs(sigma[i][j] - sigma_exact));
        }
    }
  }
  std::printf("patch test %s: max |u - u_exact| = %.2e m, max strain error = %.2e, max stress "
              "error = %.2e Pa\n",
              disc.name().c_str(), max_u_error, max_strain_error, max_stress_error);
  EXPECT_LT(max_u_error, 1e-14);
  EXPECT_LT(max_strain_error, 1e-12); // relative to 1e-3: 1e-9
  EXPECT_LT(max_stress_error, 1e-6);  // relative to 2000 Pa: 5e-10
}

TEST(PatchTest, P1) {
  run_patch(CellKind::tetrahedron, 1);
}
TEST(PatchTest, P2) {
  run_patch(CellKind::tetrahedron, 2);
}
TEST(PatchTest, Q1) {
  run_patch(CellKind::hexahedron, 1);
}
TEST(PatchTest, Q2) {
  run_patch(CellKind::hexahedron, 2);
}

} // namespace
} // namespace plantar::fem
