#pragma once
// The internal variables of a visco-hyperelastic body (fem/visco_hyperelastic_history.h) as
// per-cell fields and totals, for output and summaries: the energy its dashpots dissipated
// (ViscoHyperelasticLaw::commit) and the branches' overstresses. Loops over the cells and
// allocates: output steps only.

#include "fem/nonlinear_elasticity.h"
#include "fem/viscoelastic_cell_fields.h"

namespace plantar::fem {

/// Per active cell of @p problem at its committed state: dissipated_energy_density (J/m^3, the
/// cell mean over the reference volume; 0 in elastic cells) and overstress[i] (cell mean of
/// |Q_i|, Frobenius norm of branch i's second Piola-Kirchhoff overstress, Pa; one entry per
/// branch of the richest law); von_mises empty. All empty without viscous regions.
ViscoelasticCellFields visco_hyperelastic_cell_fields(const NonlinearElasticity& problem);

/// Energy dissipated by @p problem's dashpots since the virgin state (J): the integral of the
/// points' dissipated energy densities over the reference volume. 0 without viscous regions.
double dissipated_energy(const NonlinearElasticity& problem);

} // namespace plantar::fem
