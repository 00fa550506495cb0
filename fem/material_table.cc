#include "fem/material_table.h"

#include <sstream>
#include <stdexcept>

namespace plantar::fem {
namespace {

std::string trim(const std::string& s) {
  const auto first = s.find_first_not_of(" \t\n");
  if (first == std::string::npos)
    return "";
  return s.substr(first, s.find_last_not_of(" \t\n") - first + 1);
}

double value_of(const MaterialSpec& spec, const std::string& key) {
  const auto it = spec.values.find(key);
  if (it == spec.values.end())
    throw std::invalid_argument("material '" + spec.region + "' (law " + spec.law +
                                "): missing parameter '" + key + "'");
  return it->second;
}

} // namespace

std::map<std::string, MaterialSpec> parse_material_specs(const std::string& text,
                                                         const std::string& parameter_name) {
  std::map<std::string, MaterialSpec> specs;
  std::istringstream regions(text);
  std::string region_text;
  while (std::getline(regions, region_text, ';')) {
    region_text = trim(region_text);
    if (region_text.empty())
      continue;
    const auto colon = region_text.find(':');
    if (colon == std::string::npos)
      throw std::invalid_argument(parameter_name + ": expected 'region: key=value, ...' but got '" +
                                  region_text + "'");
    MaterialSpec spec;
    spec.region = trim(region_text.substr(0, colon));
    std::istringstream pairs(region_text.substr(colon + 1));
    std::string pair;
    while (std::getline(pairs, pair, ',')) {
      const auto equal = pair.find('=');
      if (equal == std::string::npos)
        throw std::invalid_argument(parameter_name + ": expected key=value in '" + trim(pair) +
                                    "' (region '" + spec.region + "')");
      const std::string key = trim(pair.substr(0, equal)), value = trim(pair.substr(equal + 1));
      if (key == "law") {
        spec.law = value;
        continue;
      }
      try {
        std::size_t used = 0;
        spec.values[key] = std::stod(value, &used);
        if (used != value.size())
          throw std::invalid_argument("trailing text");
      } catch (const std::exception&) {
        throw std::invalid_argument(parameter_name + ": value '" + value + "' of '" + key +
                                    "' (region '" + spec.region + "') is not a number");
      }
    }
    if (spec.region.empty() || specs.count(spec.region))
      throw std::invalid_argument(parameter_name + ": empty or repeated region name '" +
                                  spec.region + "'");
    specs[spec.region] = spec;
  }
  if (specs.empty())
    throw std::invalid_argument(parameter_name + ": no material given");
  return specs;
}

MaterialTable::MaterialTable(const std::map<std::string, MaterialSpec>& specs,
                             const PhysicalGroups& groups) {
  for (const auto& [name, spec] : specs) {
    if (groups.volumes.count(name) == 0)
      throw std::invalid_argument("material region '" + name + "' is not a physical volume of '" +
                                  groups.file.string() + "'");
    if (spec.law != "linear")
      throw std::invalid_argument(
          "material '" + name + "': law '" + spec.law +
          "' is not available to the linear solver (allowed: linear; law prony, "
          "viscoelastic, needs fem::ViscoelasticCondensation)");
    for (const auto& [key, value] : spec.values)
      if (key != "E" && key != "nu")
        throw std::invalid_argument("material '" + name + "': unknown parameter '" + key +
                                    "' for law linear (allowed: E, nu)");
    by_id_.emplace(groups.volumes.at(name),
                   LinearElasticMaterial(value_of(spec, "E"), value_of(spec, "nu"), name));
  }
  for (const auto& [name, id] : groups.volumes)
    if (groups.n_cells.count(id) && by_id_.count(id) == 0)
      throw std::invalid_argument("mesh '" + groups.file.string() + "': physical volume '" + name +
                                  "' has no material in the scene");
}

MaterialTable::MaterialTable(const LinearElasticMaterial& material) : uniform_(true) {
  by_id_.emplace(0, material);
}

const LinearElasticMaterial& MaterialTable::operator[](dealii::types::material_id id) const {
  if (uniform_)
    return by_id_.begin()->second;
  const auto it = by_id_.find(id);
  if (it == by_id_.end())
    throw std::runtime_error("no material for material id " + std::to_string(id));
  return it->second;
}

} // namespace plantar::fem
