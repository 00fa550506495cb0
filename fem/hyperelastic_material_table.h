#pragma once
// Hyperelastic laws per region of a sole, parsed from the same scene text as
// the linear MaterialTable (fem/material_table.h), e.g.
//   "top_layer: law=neo_hookean, E=8e6, nu=0.45;
//    bottom_layer: law=mooney_rivlin, C10=0.5e6, C01=0.1e6, kappa=200e6"
// Laws and their parameters (all Pa except nu):
//   neo_hookean:   E, nu (-1 < nu < 0.5)   or   mu, kappa
//   mooney_rivlin: C10, C01 and kappa or nu
// A new law registers a factory under its name (register_hyperelastic_law).

#include "fem/hyperelastic_law.h"
#include "fem/material_table.h"
#include "fem/mesh_import.h"

#include <functional>
#include <map>
#include <memory>
#include <string>

namespace plantar::fem {

using HyperelasticLawFactory = std::function<std::unique_ptr<HyperelasticLaw>(const MaterialSpec&)>;

/// Adds (or replaces) the factory of law @p law_name.
void register_hyperelastic_law(const std::string& law_name, HyperelasticLawFactory factory);

/// The law of @p spec. Throws std::invalid_argument naming the region, the
/// law and the parameter if the law is unknown, a parameter is missing,
/// unknown or out of range.
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

  /// The law of cells with material id @p id (throws std::invalid_argument if none).
  const HyperelasticLaw& operator[](dealii::types::material_id id) const;
  /// The linear-elastic table with each law's small-strain E and nu (for
  /// comparisons with the linear sole).
  MaterialTable linearized() const;

private:
  std::map<dealii::types::material_id, std::shared_ptr<const HyperelasticLaw>> by_id_;
  std::shared_ptr<const HyperelasticLaw> uniform_;
  PhysicalGroups groups_;
  std::map<std::string, dealii::types::material_id> region_ids_;
};

} // namespace plantar::fem
