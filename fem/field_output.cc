#include "fem/field_output.h"

#include "fem/atomic_file.h"

#include <deal.II/fe/fe_values.h>
#include <deal.II/numerics/data_out.h>

#include <algorithm>
#include <limits>

namespace plantar::fem {

using namespace dealii;

void StressPostprocessor::evaluate_vector_field(const DataPostprocessorInputs::Vector<3>& inputs,
                                                std::vector<Vector<double>>& computed) const {
  const auto cell = inputs.template get_cell<3>();
  const auto& material = materials_[cell->material_id()];
  for (unsigned int p = 0; p < inputs.solution_gradients.size(); ++p) {
    Tensor<2, 3> grad;
    for (unsigned int d = 0; d < 3; ++d)
      grad[d] = inputs.solution_gradients[p][d];
    const SymmetricTensor<2, 3> strain = symmetrize(grad);
    const SymmetricTensor<2, 3> stress = material.stress(strain);
    for (unsigned int i = 0; i < 3; ++i)
      for (unsigned int j = 0; j < 3; ++j) {
        computed[p](3 * i + j) = strain[i][j];
        computed[p](9 + 3 * i + j) = stress[i][j];
      }
    computed[p](18) = von_mises(stress);
  }
}

std::vector<std::string> StressPostprocessor::get_names() const {
  std::vector<std::string> names(9, "strain");
  names.resize(18, "stress");
  names.push_back("von_mises");
  return names;
}

std::vector<DataComponentInterpretation::DataComponentInterpretation>
StressPostprocessor::get_data_component_interpretation() const {
  std::vector<DataComponentInterpretation::DataComponentInterpretation> kinds(
      18, DataComponentInterpretation::component_is_part_of_tensor);
  kinds.push_back(DataComponentInterpretation::component_is_scalar);
  return kinds;
}

UpdateFlags StressPostprocessor::get_needed_update_flags() const {
  return update_gradients;
}

void StrainPostprocessor::evaluate_vector_field(const DataPostprocessorInputs::Vector<3>& inputs,
                                                std::vector<Vector<double>>& computed) const {
  for (unsigned int p = 0; p < inputs.solution_gradients.size(); ++p)
    for (unsigned int i = 0; i < 3; ++i)
      for (unsigned int j = 0; j < 3; ++j)
        computed[p](3 * i + j) =
            0.5 * (inputs.solution_gradients[p][i][j] + inputs.solution_gradients[p][j][i]);
}

std::vector<std::string> StrainPostprocessor::get_names() const {
  return std::vector<std::string>(9, "strain");
}

std::vector<DataComponentInterpretation::DataComponentInterpretation>
StrainPostprocessor::get_data_component_interpretation() const {
  return std::vector<DataComponentInterpretation::DataComponentInterpretation>(
      9, DataComponentInterpretation::component_is_part_of_tensor);
}

UpdateFlags StrainPostprocessor::get_needed_update_flags() const {
  return update_gradients;
}

void write_sole_vtu(const DoFHandler<3>& dof_handler, const Discretization& discretization,
                    const Vector<double>& solution,
                    const std::vector<const DataPostprocessor<3>*>& postprocessors,
                    const std::vector<CellField>& cell_fields, const std::filesystem::path& path) {
  DataOut<3> data_out;
  data_out.attach_dof_handler(dof_handler);
  const std::vector<std::string> names(3, "displacement");
  const std::vector<DataComponentInterpretation::DataComponentInterpretation> kinds(
      3, DataComponentInterpretation::component_is_part_of_vector);
  data_out.add_data_vector(solution, names, DataOut<3>::type_dof_data, kinds);
  for (const DataPostprocessor<3>* postprocessor : postprocessors)
    data_out.add_data_vector(solution, *postprocessor);
  for (const CellField& field : cell_fields)
    data_out.add_data_vector(*field.values, field.name, DataOut<3>::type_cell_data);
  Vector<float> material_id(dof_handler.get_triangulation().n_active_cells());
  for (const auto& cell : dof_handler.active_cell_iterators())
    material_id(cell->active_cell_index()) = cell->material_id();
  data_out.add_data_vector(material_id, "material_id", DataOut<3>::type_cell_data);
  const unsigned int subdivisions =
      discretization.kind == CellKind::hexahedron ? discretization.degree : 1;
  data_out.build_patches(*discretization.mapping, subdivisions);
  write_file_atomically(path, [&](std::ostream& out) { data_out.write_vtu(out); });
}

void write_vtu(const LinearElasticity& problem, const std::filesystem::path& path) {
  const StressPostprocessor stress(problem.materials());
  write_sole_vtu(problem.dof_handler(), problem.discretization(), problem.solution(), {&stress}, {},
                 path);
}

void write_vtu(const NonlinearElasticity& problem, const std::filesystem::path& path) {
  const Vector<float> min_j = cell_min_jacobian(problem);
  write_sole_vtu(problem.dof_handler(), problem.discretization(), problem.solution(), {},
                 {{"min_det_F", &min_j}}, path);
}

Vector<float> cell_min_jacobian(const NonlinearElasticity& problem) {
  const auto& discretization = problem.discretization();
  const auto& dof_handler = problem.dof_handler();
  FEValues<3> fe_values(*discretization.mapping, *discretization.fe, discretization.cell_quadrature,
                        update_gradients);
  const FEValuesExtractors::Vector displacement(0);
  std::vector<Tensor<2, 3>> gradients(discretization.cell_quadrature.size());
  Vector<float> result(dof_handler.get_triangulation().n_active_cells());
  for (const auto& cell : dof_handler.active_cell_iterators()) {
    fe_values.reinit(cell);
    fe_values[displacement].get_function_gradients(problem.solution(), gradients);
    double min_j = std::numeric_limits<double>::infinity();
    for (const auto& grad : gradients)
      min_j = std::min(min_j, determinant(Tensor<2, 3>(unit_symmetric_tensor<3>()) + grad));
    result(cell->active_cell_index()) = static_cast<float>(min_j);
  }
  return result;
}

} // namespace plantar::fem
