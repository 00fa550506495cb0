// Multi-material hyperelastic soles from gmsh physical volumes:
//  - graded 3-layer sole (meshes/sole_graded.geo, hexahedra), one law per
//    layer (Neo-Hookean, Mooney-Rivlin, Neo-Hookean), nu = 0, both faces
//    bonded: at small strain the layers are springs in series, exactly
//    E_eff = t / sum(t_i / E_i) (linearised solve: 1e-8; Newton at strain 1e-6: 1e-5);
//  - heel-pad sole (meshes/sole_heel_pad.geo, tetrahedra): at small strain the
//    nonlinear plate force equals the linear solver's (fem/linear_elasticity.h)
//    with the laws' small-strain E, nu (1e-4), and a 20 % compression converges.
#include "fem/mesh_generator.h"
#include "fem/nonlinear_elasticity.h"
#include "fem_test_utilities.h"

#include <gtest/gtest.h>

#include <cstdio>

namespace plantar::fem {
namespace {

constexpr double L = 0.2172, W = 0.138, T = 0.020;

TEST(MultiMaterialNonlinear, GradedSoleSpringsInSeries) {
  MeshRequest request;
  request.geo_file = testing::source_path("meshes/sole_graded.geo");
  request.numbers = {{"SoleLength", L},        {"SoleWidth", W},         {"SoleThickness", T},
                     {"BottomFraction", 0.25}, {"MiddleFraction", 0.35}, {"SoleMeshSize", 0.01},
                     {"SoleHex", 1.0}};
  request.cache_directory = testing::test_cache_dir();
  dealii::Triangulation<3> tria;
  const auto groups = import_mesh(generate_mesh(request), {"top", "bottom"}, tria);
  const double e1 = 2e6, e3 = 8e6, c10 = 0.8e6,
               c01 = 0.2e6; // middle: E = 2 mu = 4 (C10 + C01) at nu = 0
  const auto specs =
      parse_material_specs("bottom_layer: law=neo_hookean, E=2e6, nu=0; "
                           "middle_layer: law=mooney_rivlin, C10=0.8e6, C01=0.2e6, nu=0; "
                           "top_layer: law=neo_hookean, E=8e6, nu=0",
                           "Materials");
  const HyperelasticMaterialTable materials(specs, groups);
  const double e2 = 4 * (c10 + c01);
  const double t1 = 0.25 * T, t2 = 0.35 * T, t3 = T - t1 - t2;
  const double exact = T / (t1 / e1 + t2 / e2 + t3 / e3);
  const Discretization disc(CellKind::hexahedron, 1);
  for (const auto form :
       {NonlinearSettings::Formulation::displacement, NonlinearSettings::Formulation::mixed}) {
    NonlinearSettings settings;
    settings.formulation = form;
    NonlinearElasticity problem(tria, disc, materials, settings);
    const double delta = 1e-6 * T;
    const dealii::Functions::ConstantFunction<3> plate(std::vector<double>{0, 0, -delta});
    problem.setup({{groups.surface("bottom"), nullptr, {{true, true, true}}},
                   {groups.surface("top"), &plate, {{true, true, true}}}});
    problem.solve_linearized();
    const double e_lin = -problem.reaction_force(groups.surface("top"))[2] / (L * W) / (delta / T);
    const NewtonReport report = problem.solve(1);
    const double e_nl = -problem.reaction_force(groups.surface("top"))[2] / (L * W) / (delta / T);
    std::printf("%s: E_eff exact %.6e, linearised %.6e (rel %.1e), Newton %.6e (rel %.1e, %u it)\n",
                form == NonlinearSettings::Formulation::mixed ? "mixed" : "displacement", exact,
                e_lin, std::abs(e_lin / exact - 1), e_nl, std::abs(e_nl / exact - 1),
                report.iterations);
    EXPECT_NEAR(e_lin / exact, 1.0, 1e-8);
    EXPECT_NEAR(e_nl / exact, 1.0, 1e-5);
  }
}

TEST(MultiMaterialNonlinear, HeelPadSole) {
  MeshRequest request;
  request.geo_file = testing::source_path("meshes/sole_heel_pad.geo");
  request.numbers = {
      {"SoleLength", L}, {"SoleWidth", W}, {"SoleThickness", T}, {"SoleMeshSize", 0.012}};
  request.cache_directory = testing::test_cache_dir();
  dealii::Triangulation<3> tria;
  const auto groups = import_mesh(generate_mesh(request), {"top", "bottom"}, tria);
  const auto specs = parse_material_specs(
      "rubber: law=neo_hookean, E=6e6, nu=0.3; heel_pad: law=mooney_rivlin, C10=0.2e6, "
      "C01=0.05e6, nu=0.3",
      "Materials");
  const HyperelasticMaterialTable materials(specs, groups);
  const Discretization disc(CellKind::tetrahedron, 1);
  const auto bottom = groups.surface("bottom"), top = groups.surface("top");

  // Linear solver class with the small-strain constants.
  const MaterialTable linear_materials = materials.linearized();
  LinearElasticity linear(tria, disc, linear_materials);
  const double delta = 1e-6 * T;
  const dealii::Functions::ConstantFunction<3> push(std::vector<double>{0, 0, delta});
  linear.setup({{top, nullptr}, {bottom, &push}});
  linear.assemble();
  linear.solve();
  const double f_linear = linear.reaction_force(bottom)[2];

  NonlinearElasticity problem(tria, disc, materials);
  problem.setup({{top, nullptr, {{true, true, true}}}, {bottom, &push, {{true, true, true}}}});
  problem.solve(1);
  const double f_small = problem.reaction_force(bottom)[2];
  std::printf("\nheel-pad sole (%u tets): plate force at strain 1e-6: nonlinear %.6e N, "
              "linear class %.6e N, rel %.1e (tol 1e-4)\n",
              tria.n_active_cells(), f_small, f_linear, std::abs(f_small / f_linear - 1));
  EXPECT_NEAR(f_small / f_linear, 1.0, 1e-4);

  // 20 % compression.
  const dealii::Functions::ConstantFunction<3> squeeze(std::vector<double>{0, 0, 0.2 * T});
  NonlinearElasticity large(tria, disc, materials);
  large.setup({{top, nullptr, {{true, true, true}}}, {bottom, &squeeze, {{true, true, true}}}});
  const NewtonReport report = large.solve(4);
  std::printf("20 %% compression: %u Newton iterations in 4 steps, force %.4e N "
              "(linear extrapolation %.4e N), min J %.3f\n",
              report.iterations, large.reaction_force(bottom)[2], f_linear * 0.2 / 1e-6,
              report.min_jacobian);
  EXPECT_GT(report.min_jacobian, 0);
  EXPECT_GT(large.reaction_force(bottom)[2], 0);
}

} // namespace
} // namespace plantar::fem
