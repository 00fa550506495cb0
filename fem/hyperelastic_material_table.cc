#include "fem/hyperelastic_material_table.h"

#include <mutex>
#include <set>
#include <sstream>
#include <stdexcept>

namespace plantar::fem {
namespace {

std::string where(const MaterialSpec& spec) {
  return "material '" + spec.region + "' (law " + spec.law + ")";
}

void check_keys(const MaterialSpec& spec, const std::set<std::string>& allowed) {
  for (const auto& [key, value] : spec.values)
    if (allowed.count(key) == 0) {
      std::string list;
      for (const auto& name : allowed)
        list += (list.empty() ? "" : ", ") + name;
      throw std::invalid_argument(where(spec) + ": unknown parameter '" + key +
                                  "' (allowed: " + list + ")");
    }
}

double value(const MaterialSpec& spec, const std::string& key) {
  const auto it = spec.values.find(key);
  if (it == spec.values.end())
    throw std::invalid_argument(where(spec) + ": missing parameter '" + key + "'");
  return it->second;
}

bool has(const MaterialSpec& spec, const std::string& key) {
  return spec.values.count(key) > 0;
}

std::unique_ptr<HyperelasticLaw> make_neo_hookean(const MaterialSpec& spec) {
  check_keys(spec, {"E", "nu", "mu", "kappa"});
  if (has(spec, "E") || has(spec, "nu")) {
    if (has(spec, "mu") || has(spec, "kappa"))
      throw std::invalid_argument(where(spec) + ": give either E, nu or mu, kappa, not both");
    return std::make_unique<NeoHookeanLaw>(
        NeoHookeanLaw::from_youngs(value(spec, "E"), value(spec, "nu"), spec.region));
  }
  return std::make_unique<NeoHookeanLaw>(value(spec, "mu"), value(spec, "kappa"), spec.region);
}

std::unique_ptr<HyperelasticLaw> make_mooney_rivlin(const MaterialSpec& spec) {
  check_keys(spec, {"C10", "C01", "kappa", "nu"});
  const double c10 = value(spec, "C10"), c01 = value(spec, "C01");
  double kappa = 0;
  if (has(spec, "kappa") == has(spec, "nu"))
    throw std::invalid_argument(where(spec) + ": give exactly one of kappa, nu");
  if (has(spec, "kappa")) {
    kappa = value(spec, "kappa");
  } else {
    const double nu = value(spec, "nu");
    if (!(nu > -1 && nu < 0.5)) {
      std::ostringstream message;
      message << where(spec) << ": nu = " << nu << " is out of range: allowed (-1, 0.5)";
      throw std::invalid_argument(message.str());
    }
    const double mu = 2 * (c10 + c01);
    kappa = 2 * mu * (1 + nu) / (3 * (1 - 2 * nu));
  }
  return std::make_unique<MooneyRivlinLaw>(c10, c01, kappa, spec.region);
}

std::mutex registry_mutex;
std::map<std::string, HyperelasticLawFactory>& registry() {
  static std::map<std::string, HyperelasticLawFactory> factories{
      {"neo_hookean", make_neo_hookean}, {"mooney_rivlin", make_mooney_rivlin}};
  return factories;
}

} // namespace

void register_hyperelastic_law(const std::string& law_name, HyperelasticLawFactory factory) {
  std::lock_guard<std::mutex> lock(registry_mutex);
  registry()[law_name] = std::move(factory);
}

std::unique_ptr<HyperelasticLaw> make_hyperelastic_law(const MaterialSpec& full_spec) {
  MaterialSpec spec;
  split_viscous_branches(full_spec, spec);
  HyperelasticLawFactory factory;
  std::string known;
  {
    std::lock_guard<std::mutex> lock(registry_mutex);
    const auto it = registry().find(spec.law);
    if (it != registry().end())
      factory = it->second;
    for (const auto& [name, f] : registry())
      known += (known.empty() ? "" : ", ") + name;
  }
  if (!factory)
    throw std::invalid_argument("material '" + spec.region + "': law '" + spec.law +
                                "' is not a hyperelastic law (allowed: " + known + ")");
  return factory(spec);
}

HyperelasticMaterialTable::HyperelasticMaterialTable(
    const std::map<std::string, MaterialSpec>& specs, const PhysicalGroups& groups)
    : groups_(groups) {
  for (const auto& [name, spec] : specs) {
    if (groups.volumes.count(name) == 0)
      throw std::invalid_argument("material region '" + name + "' is not a physical volume of '" +
                                  groups.file.string() + "'");
    const dealii::types::material_id id = groups.volumes.at(name);
    std::shared_ptr<const HyperelasticLaw> law = make_hyperelastic_law(spec);
    MaterialSpec elastic;
    const auto branches = split_viscous_branches(spec, elastic);
    if (!branches.empty())
      viscous_by_id_[id] =
          std::make_shared<ViscoHyperelasticLaw>(law, make_viscous_branches(branches, *law));
    by_id_[id] = std::move(law);
    region_ids_[name] = id;
  }
  for (const auto& [name, id] : groups.volumes)
    if (groups.n_cells.count(id) && by_id_.count(id) == 0)
      throw std::invalid_argument("mesh '" + groups.file.string() + "': physical volume '" + name +
                                  "' has no material in the scene");
}

HyperelasticMaterialTable::HyperelasticMaterialTable(std::shared_ptr<const HyperelasticLaw> law)
    : uniform_(std::move(law)) {
  if (!uniform_)
    throw std::invalid_argument("HyperelasticMaterialTable: law is null");
}

HyperelasticMaterialTable::HyperelasticMaterialTable(
    std::shared_ptr<const ViscoHyperelasticLaw> law)
    : uniform_(law ? law->base_pointer() : nullptr), uniform_viscous_(std::move(law)) {
  if (!uniform_viscous_)
    throw std::invalid_argument("HyperelasticMaterialTable: law is null");
}

const ViscoHyperelasticLaw*
HyperelasticMaterialTable::viscous(dealii::types::material_id id) const {
  if (uniform_)
    return uniform_viscous_.get();
  const auto it = viscous_by_id_.find(id);
  return it == viscous_by_id_.end() ? nullptr : it->second.get();
}

const HyperelasticLaw& HyperelasticMaterialTable::operator[](dealii::types::material_id id) const {
  if (uniform_)
    return *uniform_;
  const auto it = by_id_.find(id);
  if (it == by_id_.end())
    throw std::invalid_argument("no hyperelastic material for material id " + std::to_string(id));
  return *it->second;
}

MaterialTable HyperelasticMaterialTable::linearized() const {
  if (uniform_)
    return MaterialTable(LinearElasticMaterial(uniform_->small_strain_youngs_modulus(),
                                               uniform_->small_strain_poisson_ratio(),
                                               uniform_->name()));
  std::map<std::string, MaterialSpec> specs;
  for (const auto& [name, id] : region_ids_) {
    const auto& law = *by_id_.at(id);
    MaterialSpec spec;
    spec.region = name;
    spec.values = {{"E", law.small_strain_youngs_modulus()},
                   {"nu", law.small_strain_poisson_ratio()}};
    specs[name] = spec;
  }
  return MaterialTable(specs, groups_);
}

} // namespace plantar::fem
