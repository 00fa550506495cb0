#include "fem/viscoelastic_material.h"

#include <cctype>
#include <cmath>
#include <sstream>
#include <stdexcept>

namespace plantar::fem {
namespace {

[[noreturn]] void out_of_range(const std::string& name, const std::string& parameter, double value,
                               const std::string& units, const std::string& allowed) {
  std::ostringstream msg;
  msg << "material '" << name << "' (law prony): " << parameter << " = " << value
      << (units.empty() ? "" : " " + units) << " is out of range: allowed " << allowed;
  throw std::invalid_argument(msg.str());
}

// Splits "tau12" into ("tau", 12); index 0 when there is no trailing number.
std::pair<std::string, unsigned int> split_key(const std::string& key) {
  std::size_t digits = key.size();
  while (digits > 0 && std::isdigit(static_cast<unsigned char>(key[digits - 1])))
    --digits;
  if (digits == key.size() || digits == 0)
    return {key, 0};
  return {key.substr(0, digits), static_cast<unsigned int>(std::stoul(key.substr(digits)))};
}

} // namespace

ViscoelasticMaterial::ViscoelasticMaterial(double shear_modulus, double bulk_modulus,
                                           std::vector<PronyBranch> branches,
                                           const std::string& name)
    : name_(name), shear_modulus_(shear_modulus), bulk_modulus_(bulk_modulus),
      branches_(std::move(branches)) {
  if (!(shear_modulus >= 0.0) || !std::isfinite(shear_modulus))
    out_of_range(name, "G_inf", shear_modulus, "Pa", "[0, inf)");
  if (!(bulk_modulus > 0.0) || !std::isfinite(bulk_modulus))
    out_of_range(name, "K_inf", bulk_modulus, "Pa", "(0, inf)");
  double instantaneous_shear = shear_modulus;
  for (std::size_t i = 0; i < branches_.size(); ++i) {
    const PronyBranch& b = branches_[i];
    const std::string index = std::to_string(i + 1);
    if (!(b.shear_modulus >= 0.0) || !std::isfinite(b.shear_modulus))
      out_of_range(name, "G" + index, b.shear_modulus, "Pa", "[0, inf)");
    if (!(b.bulk_modulus >= 0.0) || !std::isfinite(b.bulk_modulus))
      out_of_range(name, "K" + index, b.bulk_modulus, "Pa", "[0, inf)");
    if (!(b.relaxation_time > 0.0) || !std::isfinite(b.relaxation_time))
      out_of_range(name, "tau" + index, b.relaxation_time, "s", "(0, inf)");
    instantaneous_shear += b.shear_modulus;
    branch_stiffness_.push_back(isotropic_stiffness(b.shear_modulus, b.bulk_modulus));
  }
  if (!(instantaneous_shear > 0.0))
    out_of_range(name, "G_0 = G_inf + sum G_i", instantaneous_shear, "Pa", "(0, inf)");
  long_term_ = isotropic_stiffness(shear_modulus, bulk_modulus);
}

ViscoelasticMaterial ViscoelasticMaterial::from_spec(const MaterialSpec& spec) {
  const std::string& name = spec.region;
  if (spec.law == "linear") {
    for (const auto& [key, value] : spec.values)
      if (key != "E" && key != "nu")
        throw std::invalid_argument("material '" + name + "': unknown parameter '" + key +
                                    "' for law linear (allowed: E, nu)");
    for (const char* key : {"E", "nu"})
      if (spec.values.count(key) == 0)
        throw std::invalid_argument("material '" + name + "' (law linear): missing parameter '" +
                                    key + "'");
    const LinearElasticMaterial elastic(spec.values.at("E"), spec.values.at("nu"), name);
    return ViscoelasticMaterial(elastic.mu(), elastic.bulk_modulus(), {}, name);
  }
  if (spec.law != "prony")
    throw std::invalid_argument("material '" + name + "': law '" + spec.law +
                                "' is not a linear viscoelastic law (allowed: linear, prony)");
  // Long-term moduli: (E, nu) or (G, K).
  const bool young = spec.values.count("E") || spec.values.count("nu");
  const bool shear_bulk = spec.values.count("G") || spec.values.count("K");
  if (young == shear_bulk)
    throw std::invalid_argument("material '" + name +
                                "' (law prony): give the long-term moduli as E and nu, or as G "
                                "and K (not both, not neither)");
  double nu = 0;
  double shear = 0, bulk = 0;
  if (young) {
    if (!spec.values.count("E") || !spec.values.count("nu"))
      throw std::invalid_argument("material '" + name + "' (law prony): E and nu go together");
    const double E = spec.values.at("E");
    nu = spec.values.at("nu");
    if (!(nu > -1.0 && nu < 0.5))
      out_of_range(name, "nu", nu, "", "(-1, 0.5)");
    if (!(E > 0.0) || !std::isfinite(E)) // G_inf = 0 (no long-term shear): give G = 0 and K
      out_of_range(name, "E", E, "Pa", "(0, inf)");
    shear = E / (2.0 * (1.0 + nu));
    bulk = E / (3.0 * (1.0 - 2.0 * nu));
  } else {
    if (!spec.values.count("G") || !spec.values.count("K"))
      throw std::invalid_argument("material '" + name + "' (law prony): G and K go together");
    shear = spec.values.at("G");
    bulk = spec.values.at("K");
  }
  std::map<unsigned int, std::map<std::string, double>> by_branch;
  for (const auto& [key, value] : spec.values) {
    if (key == "E" || key == "nu" || key == "G" || key == "K")
      continue;
    const auto [stem, index] = split_key(key);
    if (index == 0 || (stem != "E" && stem != "G" && stem != "K" && stem != "tau"))
      throw std::invalid_argument("material '" + name + "': unknown parameter '" + key +
                                  "' for law prony (allowed: E, nu or G, K; per branch i = 1, "
                                  "2, ...: tau<i> with E<i>, or G<i> and K<i>)");
    by_branch[index][stem] = value;
  }
  std::vector<PronyBranch> branches;
  unsigned int expected = 1;
  for (const auto& [index, values] : by_branch) {
    const std::string i = std::to_string(index);
    if (index != expected)
      throw std::invalid_argument("material '" + name + "' (law prony): branch " +
                                  std::to_string(expected) +
                                  " is missing (branches are numbered "
                                  "1..N without gaps)");
    ++expected;
    if (!values.count("tau"))
      throw std::invalid_argument("material '" + name + "' (law prony): branch " + i +
                                  " has no relaxation time tau" + i);
    PronyBranch branch;
    branch.relaxation_time = values.at("tau");
    if (values.count("E")) {
      if (values.count("G") || values.count("K"))
        throw std::invalid_argument("material '" + name + "' (law prony): branch " + i +
                                    " gives E" + i + " and G" + i + "/K" + i + " (give one form)");
      if (!young)
        throw std::invalid_argument("material '" + name + "' (law prony): E" + i +
                                    " needs the long-term E and nu (the branch keeps nu)");
      const double E = values.at("E");
      if (!(E >= 0.0) || !std::isfinite(E))
        out_of_range(name, "E" + i, E, "Pa", "[0, inf)");
      branch.shear_modulus = E / (2.0 * (1.0 + nu));
      branch.bulk_modulus = E / (3.0 * (1.0 - 2.0 * nu));
    } else if (values.count("G") || values.count("K")) {
      branch.shear_modulus = values.count("G") ? values.at("G") : 0.0;
      branch.bulk_modulus = values.count("K") ? values.at("K") : 0.0;
    } else {
      throw std::invalid_argument("material '" + name + "' (law prony): branch " + i +
                                  " has no modulus (E" + i + ", or G" + i + " and K" + i + ")");
    }
    branches.push_back(branch);
  }
  return ViscoelasticMaterial(shear, bulk, std::move(branches), name);
}

double ViscoelasticMaterial::shear_relaxation(double t) const {
  double g = shear_modulus_;
  for (const PronyBranch& b : branches_)
    g += b.shear_modulus * std::exp(-t / b.relaxation_time);
  return g;
}

double ViscoelasticMaterial::bulk_relaxation(double t) const {
  double k = bulk_modulus_;
  for (const PronyBranch& b : branches_)
    k += b.bulk_modulus * std::exp(-t / b.relaxation_time);
  return k;
}

dealii::SymmetricTensor<4, 3> ViscoelasticMaterial::isotropic_stiffness(double shear, double bulk) {
  const auto identity = dealii::unit_symmetric_tensor<3>();
  const dealii::SymmetricTensor<4, 3> volumetric = dealii::outer_product(identity, identity) / 3.0;
  return 3.0 * bulk * volumetric + 2.0 * shear * (dealii::identity_tensor<3>() - volumetric);
}

dealii::SymmetricTensor<4, 3> ViscoelasticMaterial::instantaneous_stiffness() const {
  dealii::SymmetricTensor<4, 3> c = long_term_;
  for (const auto& branch : branch_stiffness_)
    c += branch;
  return c;
}

dealii::SymmetricTensor<4, 3> ViscoelasticMaterial::effective_stiffness(double dt) const {
  dealii::SymmetricTensor<4, 3> c = long_term_;
  for (unsigned int i = 0; i < n_branches(); ++i) {
    double decay = 0, gamma = 0;
    step_factors(dt, branches_[i].relaxation_time, decay, gamma);
    c += gamma * branch_stiffness_[i];
  }
  return c;
}

void ViscoelasticMaterial::step_factors(double dt, double tau, double& decay, double& gamma) {
  const double x = dt / tau;
  decay = std::exp(-x);
  gamma = -std::expm1(-x) / x; // (1 - e^-x) / x, accurate as x -> 0
}

void ViscoelasticMaterial::dissipation_weights(double x, double& w_aa, double& w_ac, double& w_cc) {
  // int_0^x E^2, 2 int E (1 - E) / x and int (1 - E)^2 / x^2 (E = exp(-s)), the last by its
  // series for small x (cancellation).
  w_aa = -0.5 * std::expm1(-2.0 * x);
  w_ac = 2.0 * (-std::expm1(-x) + 0.5 * std::expm1(-2.0 * x)) / x;
  const double one_one = x < 1e-2
                             ? x * x * x * (1.0 / 3.0 - x * (0.25 - x * (7.0 / 60.0 - x / 24.0)))
                             : x + 2.0 * std::expm1(-x) - 0.5 * std::expm1(-2.0 * x);
  w_cc = one_one / (x * x);
}

ViscoelasticMaterialTable::ViscoelasticMaterialTable(
    const std::map<std::string, MaterialSpec>& specs, const PhysicalGroups& groups) {
  for (const auto& [name, spec] : specs) {
    if (groups.volumes.count(name) == 0)
      throw std::invalid_argument("material region '" + name + "' is not a physical volume of '" +
                                  groups.file.string() + "'");
    by_id_.emplace(groups.volumes.at(name), ViscoelasticMaterial::from_spec(spec));
  }
  for (const auto& [name, id] : groups.volumes)
    if (groups.n_cells.count(id) && by_id_.count(id) == 0)
      throw std::invalid_argument("mesh '" + groups.file.string() + "': physical volume '" + name +
                                  "' has no material in the scene");
}

ViscoelasticMaterialTable::ViscoelasticMaterialTable(
    const std::map<dealii::types::material_id, ViscoelasticMaterial>& by_id)
    : by_id_(by_id) {
  if (by_id_.empty())
    throw std::invalid_argument("ViscoelasticMaterialTable: no material given");
}

ViscoelasticMaterialTable::ViscoelasticMaterialTable(const ViscoelasticMaterial& material)
    : uniform_(true) {
  by_id_.emplace(0, material);
}

const ViscoelasticMaterial&
ViscoelasticMaterialTable::operator[](dealii::types::material_id id) const {
  if (uniform_)
    return by_id_.begin()->second;
  const auto it = by_id_.find(id);
  if (it == by_id_.end())
    throw std::runtime_error("no viscoelastic material for material id " + std::to_string(id));
  return it->second;
}

} // namespace plantar::fem
