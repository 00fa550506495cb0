// Two-layer sole (meshes/sole_two_layer.geo): materials assigned by physical
// volume name; both faces bonded, top pushed down by delta. With nu = 0 the
// layers are springs in series, exactly:
//   E_eff = t / (t_top / E_top + t_bottom / E_bottom),
// and each layer's strain is sigma / E_layer (checks which layer got which E).
#include "fem/mesh_generator.h"
#include "fem_test_utilities.h"

#include <deal.II/fe/fe_values.h>
#include <gtest/gtest.h>

namespace plantar::fem {
namespace {

constexpr double L = 0.2172, W = 0.138, T = 0.020, top_fraction = 0.4;

struct Result {
  double e_eff, strain_top, strain_bottom, stress;
};

Result run(CellKind kind, double nu, double e_top, double e_bottom) {
  MeshRequest request;
  request.geo_file = testing::source_path("meshes/sole_two_layer.geo");
  request.numbers = {
      {"SoleLength", L},       {"SoleWidth", W},
      {"SoleThickness", T},    {"TopFraction", top_fraction},
      {"SoleMeshSize", 0.008}, {"SoleHex", kind == CellKind::hexahedron ? 1.0 : 0.0}};
  request.cache_directory = testing::test_cache_dir();
  dealii::Triangulation<3> tria;
  const auto groups = import_mesh(generate_mesh(request), {"top", "bottom"}, tria);
  const auto specs =
      parse_material_specs("top_layer: E=" + std::to_string(e_top) + ", nu=" + std::to_string(nu) +
                               "; bottom_layer: law=linear, E=" + std::to_string(e_bottom) +
                               ", nu=" + std::to_string(nu),
                           "Materials");
  const MaterialTable materials(specs, groups);
  const Discretization disc(kind, 1);
  LinearElasticity problem(tria, disc, materials);
  const double delta = 1e-4;
  const dealii::Functions::ConstantFunction<3> plate(std::vector<double>{0, 0, -delta});
  problem.setup({{groups.surface("bottom"), nullptr}, {groups.surface("top"), &plate}});
  problem.assemble();
  problem.solve();
  Result r;
  r.stress = -problem.reaction_force(groups.surface("top"))[2] / (L * W);
  r.e_eff = r.stress / (delta / T);
  // Mean eps_zz per layer.
  dealii::FEValues<3> fe_values(*disc.mapping, *disc.fe, disc.cell_quadrature,
                                dealii::update_gradients | dealii::update_JxW_values);
  std::vector<dealii::SymmetricTensor<2, 3>> strains(disc.cell_quadrature.size());
  std::map<dealii::types::material_id, std::pair<double, double>> sums;
  for (const auto& cell : problem.dof_handler().active_cell_iterators()) {
    fe_values.reinit(cell);
    fe_values[dealii::FEValuesExtractors::Vector(0)].get_function_symmetric_gradients(
        problem.solution(), strains);
    for (unsigned int q = 0; q < strains.size(); ++q) {
      sums[cell->material_id()].first += strains[q][2][2] * fe_values.JxW(q);
      sums[cell->material_id()].second += fe_values.JxW(q);
    }
  }
  const auto& top = sums[groups.volume("top_layer")];
  const auto& bottom = sums[groups.volume("bottom_layer")];
  r.strain_top = -top.first / top.second;
  r.strain_bottom = -bottom.first / bottom.second;
  return r;
}

TEST(MultiMaterial, TwoLayersInSeries) {
  const double e_top = 8e6, e_bottom = 2e6;
  const double series = T / (top_fraction * T / e_top + (1 - top_fraction) * T / e_bottom);
  for (const auto kind : {CellKind::tetrahedron, CellKind::hexahedron}) {
    const Result r = run(kind, 0.0, e_top, e_bottom);
    std::printf("%s: E_eff = %.6e Pa, series %.6e Pa (%.2e rel); strain top %.4e (sigma/E %.4e), "
                "bottom %.4e (sigma/E %.4e)\n",
                kind == CellKind::hexahedron ? "Q1" : "P1", r.e_eff, series, r.e_eff / series - 1,
                r.strain_top, r.stress / e_top, r.strain_bottom, r.stress / e_bottom);
    EXPECT_NEAR(r.e_eff / series, 1.0, 0.02);
    EXPECT_NEAR(r.strain_top / (r.stress / e_top), 1.0, 0.02);
    EXPECT_NEAR(r.strain_bottom / (r.stress / e_bottom), 1.0, 0.02);
  }
}

} // namespace
} // namespace plantar::fem
