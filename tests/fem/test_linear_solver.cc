// The iterative PETSc path (CG + BoomerAMG) against the sparse direct solver
// on the default sole under a uniform 600 N ground reaction.
#include "fem/mesh_generator.h"
#include "fem_test_utilities.h"

#include <gtest/gtest.h>

namespace plantar::fem {
namespace {

TEST(LinearSolver, IterativeMatchesDirect) {
  MeshRequest request;
  request.geo_file = testing::source_path("meshes/sole_box.geo");
  request.numbers = {{"SoleMeshSize", 0.008}, {"SoleHex", 0}};
  request.cache_directory = testing::test_cache_dir();
  dealii::Triangulation<3> tria;
  const auto groups = import_mesh(generate_mesh(request), {"top", "bottom"}, tria);
  const MaterialTable materials(LinearElasticMaterial(4e6, 0.3));
  const Discretization disc(CellKind::tetrahedron, 2);
  LinearElasticity problem(tria, disc, materials);
  problem.setup({{groups.surface("top"), nullptr}});
  problem.assemble();
  problem.add_traction(groups.surface("bottom"),
                       dealii::Tensor<1, 3>({0, 0, 600.0 / (0.2172 * 0.138)}));
  problem.solve();
  const dealii::Vector<double> direct = problem.solution();

  LinearSolverSettings iterative;
  iterative.kind = LinearSolverSettings::Kind::iterative;
  iterative.relative_tolerance = 1e-12;
  problem.factorize(iterative);
  problem.solve();
  dealii::Vector<double> difference = problem.solution();
  difference -= direct;
  const double relative = difference.l2_norm() / direct.l2_norm();
  std::printf("%u dofs: CG + BoomerAMG %u iterations, |u_it - u_direct| / |u_direct| = %.2e\n",
              problem.dof_handler().n_dofs(), problem.solver().last_iterations(), relative);
  EXPECT_LT(relative, 1e-8);
  // Equilibrium: the reaction on the attached face balances the 600 N.
  const auto reaction = problem.reaction_force(groups.surface("top"));
  std::printf("reaction on top = (%.3e, %.3e, %.6f) N\n", reaction[0], reaction[1], reaction[2]);
  EXPECT_NEAR(reaction[2], -600.0, 600.0 * 1e-8);
}

TEST(LinearSolver, IterativeNonConvergenceIsReported) {
  dealii::Triangulation<3> tria;
  testing::make_box(tria, CellKind::hexahedron, 8, 8, 2, 1, 1, 0.1);
  const MaterialTable materials(LinearElasticMaterial(1e6, 0.3));
  const Discretization disc(CellKind::hexahedron, 1);
  LinearElasticity problem(tria, disc, materials);
  problem.setup({{5, nullptr}});
  problem.assemble();
  problem.add_traction(4, dealii::Tensor<1, 3>({0, 0, 1e3}));
  LinearSolverSettings settings;
  settings.kind = LinearSolverSettings::Kind::iterative;
  settings.relative_tolerance = 1e-14;
  settings.max_iterations = 2;
  try {
    problem.solve(settings);
    FAIL() << "expected a convergence failure";
  } catch (const std::runtime_error& e) {
    std::printf("message: %s\n", e.what());
    EXPECT_NE(std::string(e.what()).find("did not converge"), std::string::npos);
  }
}

} // namespace
} // namespace plantar::fem
