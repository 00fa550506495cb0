#include "fem/field_output.h"

#include "fem/atomic_file.h"

#include <deal.II/numerics/data_out.h>

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

void write_vtu(const LinearElasticity& problem, const std::filesystem::path& path) {
  const StressPostprocessor postprocessor(problem.materials());
  DataOut<3> data_out;
  data_out.attach_dof_handler(problem.dof_handler());
  const std::vector<std::string> names(3, "displacement");
  const std::vector<DataComponentInterpretation::DataComponentInterpretation> kinds(
      3, DataComponentInterpretation::component_is_part_of_vector);
  data_out.add_data_vector(problem.solution(), names, DataOut<3>::type_dof_data, kinds);
  data_out.add_data_vector(problem.solution(), postprocessor);
  Vector<float> material_id(problem.dof_handler().get_triangulation().n_active_cells());
  for (const auto& cell : problem.dof_handler().active_cell_iterators())
    material_id(cell->active_cell_index()) = cell->material_id();
  data_out.add_data_vector(material_id, "material_id", DataOut<3>::type_cell_data);
  const auto& discretization = problem.discretization();
  const unsigned int subdivisions =
      discretization.kind == CellKind::hexahedron ? discretization.degree : 1;
  data_out.build_patches(*discretization.mapping, subdivisions);
  write_file_atomically(path, [&](std::ostream& out) { data_out.write_vtu(out); });
}

} // namespace plantar::fem
