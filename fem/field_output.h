#pragma once
// The sole's fields for ParaView: displacement (m), small strain, Cauchy
// stress (Pa), von Mises stress (Pa) and the per-cell material id, written as
// a VTU file (written to a temporary file, then renamed).

#include "fem/linear_elasticity.h"

#include <deal.II/numerics/data_postprocessor.h>

#include <filesystem>

namespace plantar::fem {

/// Strain eps = sym grad u, stress sigma = C : eps (C of the cell's material),
/// and von Mises stress, evaluated at the output points.
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

/// Writes @p problem's solution and derived fields to @p path (.vtu).
/// Q2/P2 fields are sampled on subdivided patches (hexahedra) or at the
/// vertices (tetrahedra).
void write_vtu(const LinearElasticity& problem, const std::filesystem::path& path);

} // namespace plantar::fem
