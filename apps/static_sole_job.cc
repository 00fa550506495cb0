#include "apps/static_sole_job.h"

#include "fem/discretization.h"
#include "fem/field_output.h"
#include "fem/linear_elasticity.h"
#include "fem/material_table.h"
#include "fem/mesh_import.h"

#include <chrono>

namespace plantar::app {

fem::MaterialTable sole_material_table(const Scene& scene, const fem::PhysicalGroups& groups) {
  try {
    return fem::MaterialTable(fem::parse_material_specs(scene.sole.materials, "Sole/Materials"),
                              groups);
  } catch (const std::invalid_argument& e) {
    throw std::invalid_argument("Sole/Materials against '" + scene.sole.geometry_file.string() +
                                "': " + e.what());
  }
}

StaticSoleResult run_static_sole(const Scene& scene, const std::filesystem::path& output) {
  const auto start = std::chrono::steady_clock::now();
  auto request = scene.sole.mesh_request();
  if (request.cache_directory.empty())
    request.cache_directory = fem::default_mesh_cache();
  const auto msh = fem::generate_mesh(request);
  dealii::Triangulation<3> tria;
  const auto groups = fem::import_mesh(msh, {"top", "bottom"}, tria);
  if (fem::cell_kind(tria) != scene.sole.cell_kind)
    throw std::runtime_error("mesh '" + msh.string() + "' does not hold the requested cell kind");
  const fem::MaterialTable materials = sole_material_table(scene, groups);
  const fem::Discretization disc(scene.sole.cell_kind, scene.sole.degree);
  fem::LinearElasticity problem(tria, disc, materials);
  problem.setup({{groups.surface("top"), nullptr}});
  problem.assemble();
  const double area = scene.sole.length * scene.sole.width;
  const auto& load = scene.static_load;
  problem.add_traction(groups.surface("bottom"),
                       dealii::Tensor<1, 3>({load.tangential_x / area, load.tangential_y / area,
                                             load.normal_force / area}));
  problem.solve(scene.sole.solver);

  StaticSoleResult result;
  result.n_cells = tria.n_active_cells();
  result.n_dofs = problem.dof_handler().n_dofs();
  result.max_displacement = problem.max_displacement();
  const auto bottom = problem.boundary_nodes(groups.surface("bottom"));
  for (const auto& node : bottom)
    result.mean_bottom_uz += problem.solution()[node[2]] / bottom.size();
  result.reaction_z = problem.reaction_force(groups.surface("top"))[2];
  if (scene.output.write_vtu)
    fem::write_vtu(problem, output / "sole.vtu");
  result.wall_time =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return result;
}

} // namespace plantar::app
