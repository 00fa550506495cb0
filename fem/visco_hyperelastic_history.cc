#include "fem/visco_hyperelastic_history.h"

#include <algorithm>

namespace plantar::fem {

ViscoHyperelasticHistory::ViscoHyperelasticHistory(const dealii::Triangulation<3>& triangulation,
                                                   const HyperelasticMaterialTable& materials,
                                                   unsigned int n_quadrature_points)
    : n_q_(n_quadrature_points) {
  const unsigned int n_cells = triangulation.n_active_cells();
  laws_.assign(n_cells, nullptr);
  point_offset_.assign(n_cells, 0);
  overstress_offset_.assign(n_cells, 0);
  unsigned int n_points = 0, n_overstress = 0;
  for (const auto& cell : triangulation.active_cell_iterators()) {
    const unsigned int c = cell->active_cell_index();
    laws_[c] = materials.viscous(cell->material_id());
    point_offset_[c] = n_points;
    overstress_offset_[c] = n_overstress;
    if (laws_[c] != nullptr) {
      n_points += n_q_;
      n_overstress += n_q_ * laws_[c]->n_branches();
    }
  }
  isochoric_.assign(n_points, {});
  trial_.assign(n_points, {});
  overstress_.assign(n_overstress, {});
  dissipation_.assign(n_points, 0.0);
}

void ViscoHyperelasticHistory::evaluate(unsigned int cell, unsigned int q,
                                        const dealii::Tensor<2, 3>& F, bool include_volumetric,
                                        double dt, StressTangent& out) {
  const ViscoHyperelasticLaw& law = *laws_[cell];
  const unsigned int point = point_offset_[cell] + q;
  ViscoPointState state;
  state.isochoric_stress = isochoric_[point];
  state.overstress = overstress_.data() + overstress_offset_[cell] + q * law.n_branches();
  law.evaluate(F, include_volumetric, dt, state, out, trial_[point]);
}

void ViscoHyperelasticHistory::commit(double dt) {
  for (unsigned int c = 0; c < laws_.size(); ++c) {
    if (laws_[c] == nullptr)
      continue;
    const unsigned int n_b = laws_[c]->n_branches();
    for (unsigned int q = 0; q < n_q_; ++q) {
      const unsigned int point = point_offset_[c] + q;
      dissipation_[point] += laws_[c]->commit(dt, isochoric_[point], trial_[point],
                                              overstress_.data() + overstress_offset_[c] + q * n_b);
      isochoric_[point] = trial_[point];
    }
  }
}

void ViscoHyperelasticHistory::reset() {
  for (auto* v : {&isochoric_, &trial_, &overstress_})
    for (auto& t : *v)
      t = 0;
  std::fill(dissipation_.begin(), dissipation_.end(), 0.0);
}

dealii::SymmetricTensor<2, 3> ViscoHyperelasticHistory::total_overstress(unsigned int cell,
                                                                         unsigned int q) const {
  dealii::SymmetricTensor<2, 3> sum;
  const unsigned int n_b = laws_[cell]->n_branches();
  for (unsigned int i = 0; i < n_b; ++i)
    sum += overstress_[overstress_offset_[cell] + q * n_b + i];
  return sum;
}

} // namespace plantar::fem
