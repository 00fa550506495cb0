#pragma once
// Internal variables of the visco-hyperelastic regions of a body (Data; the laws are
// fem/visco_hyperelastic_law.h): per quadrature point the committed isochoric stress S_iso^n
// and overstresses Q_i^n (one per branch), and the trial S_iso^{n+1} of the latest evaluation.
// Evaluations never touch the committed state, so a failed Newton solve leaves it as it was
// (rollback = not committing); commit() advances it at a converged state.

#include "fem/hyperelastic_material_table.h"

#include <deal.II/base/symmetric_tensor.h>
#include <deal.II/grid/tria.h>

#include <vector>

namespace plantar::fem {

class ViscoHyperelasticHistory {
public:
  /// Storage for every active cell of @p triangulation (by active_cell_index) with
  /// @p n_quadrature_points points; cells of elastic regions store nothing. Zero state (the
  /// virgin material). @p materials must outlive this object.
  ViscoHyperelasticHistory(const dealii::Triangulation<3>& triangulation,
                           const HyperelasticMaterialTable& materials,
                           unsigned int n_quadrature_points);

  /// True if active cell @p cell has a viscous law.
  bool is_viscous(unsigned int cell) const { return laws_[cell] != nullptr; }

  /// Algorithmic stress and tangent of point @p q of viscous cell @p cell at @p F after a step
  /// @p dt (s) from the committed state (ViscoHyperelasticLaw::evaluate); records the trial
  /// S_iso. No heap allocation.
  void evaluate(unsigned int cell, unsigned int q, const dealii::Tensor<2, 3>& F,
                bool include_volumetric, double dt, StressTangent& out);

  /// Advances every viscous point by the step @p dt (s) to its latest trial state:
  /// Q_i <- e_i Q_i + beta_i gamma_i (S_iso_trial - S_iso), S_iso <- S_iso_trial, and adds the
  /// step's dissipation (ViscoHyperelasticLaw::commit) to each point's.
  void commit(double dt);
  /// Back to the virgin state (all zero).
  void reset();

  /// Committed S_iso^n and sum_i Q_i^n (Pa) at point @p q of viscous cell @p cell.
  const dealii::SymmetricTensor<2, 3>& isochoric_stress(unsigned int cell, unsigned int q) const {
    return isochoric_[point_offset_[cell] + q];
  }
  dealii::SymmetricTensor<2, 3> total_overstress(unsigned int cell, unsigned int q) const;
  /// Committed Q_i^n (Pa) of branch @p i at point @p q of viscous cell @p cell.
  const dealii::SymmetricTensor<2, 3>& overstress(unsigned int cell, unsigned int q,
                                                  unsigned int i) const {
    return overstress_[overstress_offset_[cell] + q * laws_[cell]->n_branches() + i];
  }
  /// Number of branches of cell @p cell's law (0 for an elastic cell).
  unsigned int n_branches(unsigned int cell) const {
    return laws_[cell] != nullptr ? laws_[cell]->n_branches() : 0;
  }
  /// Energy the dashpots dissipated at point @p q of viscous cell @p cell since the virgin
  /// state, per unit reference volume (J/m^3).
  double dissipated_energy_density(unsigned int cell, unsigned int q) const {
    return dissipation_[point_offset_[cell] + q];
  }

private:
  unsigned int n_q_;
  std::vector<const ViscoHyperelasticLaw*> laws_; // per cell, nullptr: elastic
  std::vector<unsigned int> point_offset_;        // per cell, into isochoric_, trial_
  std::vector<unsigned int> overstress_offset_;   // per cell, into overstress_
  std::vector<dealii::SymmetricTensor<2, 3>> isochoric_, trial_, overstress_;
  std::vector<double> dissipation_; // per point, J/m^3
};

} // namespace plantar::fem
