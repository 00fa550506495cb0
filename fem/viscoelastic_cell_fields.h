#pragma once
// The per-cell fields of a viscoelastic body for its .vtu (fem/viscoelastic_condensation.h's
// linear sole, fem/visco_hyperelastic_fields.h's finite-strain one).

#include <vector>

namespace plantar::fem {

/// Per active cell (indexed by active_cell_index()), for output: written with the sole's .vtu.
struct ViscoelasticCellFields {
  /// Energy dissipated in the cell since rest, per unit (undeformed) volume, J/m^3.
  std::vector<double> dissipated_energy_density;
  /// Von Mises stress of the cell-mean stress sigma^n = C_inf : eps^n + sum_i h_i^n, Pa (the
  /// linear law; empty for the finite-strain law, whose stress the point fields give).
  std::vector<double> von_mises;
  /// overstress[i][cell]: cell mean of |h_i| (Frobenius norm of branch i's overstress, Pa);
  /// 0 in regions with fewer than i + 1 branches. One entry per branch of the richest region.
  std::vector<std::vector<double>> overstress;
};

} // namespace plantar::fem
