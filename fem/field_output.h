#pragma once
// The sole's fields for ParaView, one writer for the linear and the
// hyperelastic sole: a VTU file (written to a temporary file, then renamed)
// with, in this order,
//   point data: displacement (3, m), then the fields of the postprocessors
//               passed (linear sole: StressPostprocessor: strain (3 x 3),
//               Cauchy stress (3 x 3, Pa), von_mises (Pa));
//   cell data:  the per-cell fields passed (hyperelastic sole: min_det_F),
//               then material_id.
// Q2/P2 fields are sampled on subdivided patches (hexahedra, `degree`
// subdivisions) or at the vertices (tetrahedra).

#include "fem/discretization.h"
#include "fem/linear_elasticity.h"
#include "fem/nonlinear_elasticity.h"

#include <deal.II/dofs/dof_handler.h>
#include <deal.II/lac/vector.h>
#include <deal.II/numerics/data_postprocessor.h>

#include <filesystem>
#include <string>
#include <vector>

namespace plantar::fem {

/// Small strain eps = sym grad u (3 x 3), stress sigma = C : eps (3 x 3, Pa;
/// C of the cell's material) and von Mises stress (Pa), at the output points:
/// 19 components named strain (9), stress (9), von_mises.
class StressPostprocessor : public dealii::DataPostprocessor<3> {
public:
  explicit StressPostprocessor(const MaterialTable& materials) : materials_(materials) {}
  void evaluate_vector_field(const dealii::DataPostprocessorInputs::Vector<3>& inputs,
                             std::vector<dealii::Vector<double>>& computed) const override;
  std::vector<std::string> get_names() const override;
  std::vector<dealii::DataComponentInterpretation::DataComponentInterpretation>
  get_data_component_interpretation() const override;
  dealii::UpdateFlags get_needed_update_flags() const override;

private:
  const MaterialTable& materials_;
};

/// Small strain eps = sym grad u (3 x 3) at the output points: 9 components named strain (a
/// viscoelastic sole's stress depends on its history, written per cell instead).
class StrainPostprocessor : public dealii::DataPostprocessor<3> {
public:
  void evaluate_vector_field(const dealii::DataPostprocessorInputs::Vector<3>& inputs,
                             std::vector<dealii::Vector<double>>& computed) const override;
  std::vector<std::string> get_names() const override;
  std::vector<dealii::DataComponentInterpretation::DataComponentInterpretation>
  get_data_component_interpretation() const override;
  dealii::UpdateFlags get_needed_update_flags() const override;
};

/// A per-cell field of the output: @p values has one entry per active cell
/// (indexed by active_cell_index()).
struct CellField {
  std::string name;
  const dealii::Vector<float>* values = nullptr;
};

/// The one sole writer (see the top of this file): the displacement field
/// @p solution (n_dofs, m) on @p dof_handler / @p discretization, the derived
/// point fields of @p postprocessors (evaluated on @p solution), the cell
/// fields @p cell_fields and the material ids, to @p path (.vtu).
/// Throws std::runtime_error naming the file if it cannot be written.
void write_sole_vtu(const dealii::DoFHandler<3>& dof_handler, const Discretization& discretization,
                    const dealii::Vector<double>& solution,
                    const std::vector<const dealii::DataPostprocessor<3>*>& postprocessors,
                    const std::vector<CellField>& cell_fields, const std::filesystem::path& path);

/// Linear sole: displacement, strain, stress, von_mises, material_id.
void write_vtu(const LinearElasticity& problem, const std::filesystem::path& path);

/// Hyperelastic sole: displacement (current state), min_det_F, material_id.
void write_vtu(const NonlinearElasticity& problem, const std::filesystem::path& path);

/// Per-cell minimum of det F = det(I + grad u) over the quadrature points
/// (size n_active_cells) of @p problem's current displacement.
dealii::Vector<float> cell_min_jacobian(const NonlinearElasticity& problem);

} // namespace plantar::fem
