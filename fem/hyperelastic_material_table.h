#pragma once
// Hyperelastic laws per region of a sole, parsed from the same scene text as
// the linear MaterialTable (fem/material_table.h), e.g.
//   "top_layer: law=neo_hookean, E=8e6, nu=0.45;
//    bottom_layer: law=mooney_rivlin, C10=0.5e6, C01=0.1e6, kappa=200e6"
// Laws and their parameters (all Pa except nu):
//   neo_hookean:   E, nu (-1 < nu < 0.5)   or   mu, kappa
//   mooney_rivlin: C10, C01 and kappa or nu
// A new law registers a factory under its name (register_hyperelastic_law).
// Any law takes relaxing isochoric branches (fem/visco_hyperelastic_law.h):
//   "rubber: law=neo_hookean, E=2e6, nu=0.45, beta1=1.5, tau1=1e-3"
// the table then holds a ViscoHyperelasticLaw for that region (viscous()).

#include "fem/hyperelastic_law.h"
#include "fem/material_table.h"
#include "fem/mesh_import.h"
#include "fem/visco_hyperelastic_law.h"

#include <functional>
#include <map>
#include <memory>
#include <string>

namespace plantar::fem {

using HyperelasticLawFactory = std::function<std::unique_ptr<HyperelasticLaw>(const MaterialSpec&)>;

/// Adds (or replaces) the factory of law @p law_name.
void register_hyperelastic_law(const std::string& law_name, HyperelasticLawFactory factory);

/// The (long-term, elastic) law of @p spec. Throws std::invalid_argument naming the region, the
/// law and the parameter if the law is unknown, a parameter is missing, unknown or out of
/// range. Viscous branch keys (beta<i>, G<i>, tau<i>) are checked and left out of the law.
std::unique_ptr<HyperelasticLaw> make_hyperelastic_law(const MaterialSpec& spec);

/// Hyperelastic laws indexed by deal.II material id.
class HyperelasticMaterialTable {
public:
  /// Resolves @p specs against the mesh's physical volumes (every volume
  /// holding cells needs a spec, every spec a volume; throws
  /// std::invalid_argument naming the region and the mesh file otherwise).
  HyperelasticMaterialTable(const std::map<std::string, MaterialSpec>& specs,
                            const PhysicalGroups& groups);
  /// One law for every cell whatever its id.
  explicit HyperelasticMaterialTable(std::shared_ptr<const HyperelasticLaw> law);
  /// One visco-hyperelastic law for every cell (its base law is operator[]).
  explicit HyperelasticMaterialTable(std::shared_ptr<const ViscoHyperelasticLaw> law);

  /// The law of cells with material id @p id (throws std::invalid_argument if none).
  const HyperelasticLaw& operator[](dealii::types::material_id id) const;
  /// The visco-hyperelastic law of cells with id @p id, nullptr where the region is elastic
  /// (no branch). Its base() is operator[](id).
  const ViscoHyperelasticLaw* viscous(dealii::types::material_id id) const;
  /// True if some region has a viscous branch.
  bool has_viscosity() const { return uniform_viscous_ || !viscous_by_id_.empty(); }
  /// The linear-elastic table with each law's small-strain E and nu (for
  /// comparisons with the linear sole).
  MaterialTable linearized() const;

private:
  std::map<dealii::types::material_id, std::shared_ptr<const HyperelasticLaw>> by_id_;
  std::shared_ptr<const HyperelasticLaw> uniform_;
  std::map<dealii::types::material_id, std::shared_ptr<const ViscoHyperelasticLaw>> viscous_by_id_;
  std::shared_ptr<const ViscoHyperelasticLaw> uniform_viscous_;
  PhysicalGroups groups_;
  std::map<std::string, dealii::types::material_id> region_ids_;
};

} // namespace plantar::fem
