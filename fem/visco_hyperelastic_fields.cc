#include "fem/visco_hyperelastic_fields.h"

#include "fem/visco_hyperelastic_history.h"

#include <deal.II/fe/fe_values.h>

#include <algorithm>

namespace plantar::fem {

namespace {
// Calls visit(cell index, q, JxW) for every quadrature point of every viscous cell.
template <typename Visit>
void for_each_viscous_point(const NonlinearElasticity& problem,
                            const ViscoHyperelasticHistory& history, Visit visit) {
  const Discretization& discretization = problem.discretization();
  dealii::FEValues<3> fe_values(*discretization.mapping, *discretization.fe,
                                discretization.cell_quadrature, dealii::update_JxW_values);
  for (const auto& cell : problem.dof_handler().active_cell_iterators()) {
    const unsigned int index = cell->active_cell_index();
    if (!history.is_viscous(index))
      continue;
    fe_values.reinit(cell);
    for (unsigned int q = 0; q < fe_values.n_quadrature_points; ++q)
      visit(index, q, fe_values.JxW(q));
  }
}
} // namespace

ViscoelasticCellFields visco_hyperelastic_cell_fields(const NonlinearElasticity& problem) {
  ViscoelasticCellFields fields;
  const ViscoHyperelasticHistory* history = problem.history();
  if (history == nullptr)
    return fields;
  const unsigned int n_cells = problem.dof_handler().get_triangulation().n_active_cells();
  unsigned int n_branches = 0;
  for (unsigned int c = 0; c < n_cells; ++c)
    n_branches = std::max(n_branches, history->n_branches(c));
  fields.dissipated_energy_density.assign(n_cells, 0.0);
  fields.overstress.assign(n_branches, std::vector<double>(n_cells, 0.0));
  std::vector<double> volume(n_cells, 0.0);
  for_each_viscous_point(problem, *history, [&](unsigned int c, unsigned int q, double jxw) {
    fields.dissipated_energy_density[c] += history->dissipated_energy_density(c, q) * jxw;
    for (unsigned int i = 0; i < history->n_branches(c); ++i)
      fields.overstress[i][c] += history->overstress(c, q, i).norm() * jxw;
    volume[c] += jxw;
  });
  for (unsigned int c = 0; c < n_cells; ++c) {
    if (!(volume[c] > 0))
      continue;
    fields.dissipated_energy_density[c] /= volume[c];
    for (auto& branch : fields.overstress)
      branch[c] /= volume[c];
  }
  return fields;
}

double dissipated_energy(const NonlinearElasticity& problem) {
  const ViscoHyperelasticHistory* history = problem.history();
  if (history == nullptr)
    return 0.0;
  double energy = 0;
  for_each_viscous_point(problem, *history, [&](unsigned int c, unsigned int q, double jxw) {
    energy += history->dissipated_energy_density(c, q) * jxw;
  });
  return energy;
}

} // namespace plantar::fem
