#include "fem/nonlinear_output.h"

#include "fem/atomic_file.h"

#include <deal.II/fe/fe_values.h>
#include <deal.II/numerics/data_out.h>

#include <limits>

namespace plantar::fem {

dealii::Vector<float> cell_min_jacobian(const NonlinearElasticity& problem) {
  const auto& discretization = problem.discretization();
  const auto& dof_handler = problem.dof_handler();
  dealii::FEValues<3> fe_values(*discretization.mapping, *discretization.fe,
                                discretization.cell_quadrature, dealii::update_gradients);
  const dealii::FEValuesExtractors::Vector displacement(0);
  std::vector<dealii::Tensor<2, 3>> gradients(discretization.cell_quadrature.size());
  dealii::Vector<float> result(dof_handler.get_triangulation().n_active_cells());
  for (const auto& cell : dof_handler.active_cell_iterators()) {
    fe_values.reinit(cell);
    fe_values[displacement].get_function_gradients(problem.solution(), gradients);
    double min_j = std::numeric_limits<double>::infinity();
    for (const auto& grad : gradients)
      min_j = std::min(min_j, dealii::determinant(
                                  dealii::Tensor<2, 3>(dealii::unit_symmetric_tensor<3>()) + grad));
    result(cell->active_cell_index()) = static_cast<float>(min_j);
  }
  return result;
}

void write_vtu(const NonlinearElasticity& problem, const std::filesystem::path& path) {
  dealii::DataOut<3> data_out;
  data_out.attach_dof_handler(problem.dof_handler());
  const std::vector<std::string> names(3, "displacement");
  const std::vector<dealii::DataComponentInterpretation::DataComponentInterpretation> kinds(
      3, dealii::DataComponentInterpretation::component_is_part_of_vector);
  data_out.add_data_vector(problem.solution(), names, dealii::DataOut<3>::type_dof_data, kinds);
  const dealii::Vector<float> min_j = cell_min_jacobian(problem);
  data_out.add_data_vector(min_j, "min_det_F", dealii::DataOut<3>::type_cell_data);
  dealii::Vector<float> material_id(min_j.size());
  for (const auto& cell : problem.dof_handler().active_cell_iterators())
    material_id(cell->active_cell_index()) = cell->material_id();
  data_out.add_data_vector(material_id, "material_id", dealii::DataOut<3>::type_cell_data);
  const auto& discretization = problem.discretization();
  const unsigned int subdivisions =
      discretization.kind == CellKind::hexahedron ? discretization.degree : 1;
  data_out.build_patches(*discretization.mapping, subdivisions);
  write_file_atomically(path, [&](std::ostream& out) { data_out.write_vtu(out); });
}

} // namespace plantar::fem
