#include "fem/visco_hyperelastic_law.h"

#include "fem/viscoelastic_material.h"

#include <cctype>
#include <cmath>
#include <map>
#include <sstream>
#include <stdexcept>

namespace plantar::fem {
namespace {

std::string region_text(const std::string& name) {
  return name.empty() ? std::string("material") : "material '" + name + "'";
}

[[noreturn]] void out_of_range(const std::string& where, const std::string& parameter, double value,
                               const std::string& allowed) {
  std::ostringstream message;
  message << where << ": " << parameter << " = " << value << " is out of range: allowed "
          << allowed;
  throw std::invalid_argument(message.str());
}

// "tau12" -> ("tau", 12); index 0 when there is no trailing number or no stem.
std::pair<std::string, unsigned int> split_key(const std::string& key) {
  std::size_t digits = key.size();
  while (digits > 0 && std::isdigit(static_cast<unsigned char>(key[digits - 1])))
    --digits;
  if (digits == key.size() || digits == 0 || key.size() - digits > 6)
    return {key, 0};
  return {key.substr(0, digits), static_cast<unsigned int>(std::stoul(key.substr(digits)))};
}

} // namespace

ViscoHyperelasticLaw::ViscoHyperelasticLaw(std::shared_ptr<const HyperelasticLaw> base,
                                           std::vector<ViscousBranch> branches)
    : base_(std::move(base)), branches_(std::move(branches)) {
  if (!base_)
    throw std::invalid_argument("ViscoHyperelasticLaw: base law is null");
  for (std::size_t i = 0; i < branches_.size(); ++i) {
    const std::string index = std::to_string(i + 1);
    if (!(branches_[i].beta >= 0) || !std::isfinite(branches_[i].beta))
      out_of_range(region_text(name()) + " (visco-hyperelastic)", "beta" + index, branches_[i].beta,
                   "[0, inf)");
    if (!(branches_[i].relaxation_time > 0) || !std::isfinite(branches_[i].relaxation_time))
      out_of_range(region_text(name()) + " (visco-hyperelastic)", "tau" + index,
                   branches_[i].relaxation_time, "(0, inf) s");
  }
}

double ViscoHyperelasticLaw::instantaneous_shear_modulus() const {
  double factor = 1;
  for (const ViscousBranch& b : branches_)
    factor += b.beta;
  return factor * base_->small_strain_shear_modulus();
}

void ViscoHyperelasticLaw::step_factors(unsigned int i, double dt, double& decay,
                                        double& gamma) const {
  const double x = dt / branches_[i].relaxation_time;
  decay = std::exp(-x);
  gamma = -std::expm1(-x) / x; // (1 - e^-x) / x, accurate as x -> 0
}

void ViscoHyperelasticLaw::evaluate(const dealii::Tensor<2, 3>& F, bool include_volumetric,
                                    double dt, const ViscoPointState& state, StressTangent& out,
                                    dealii::SymmetricTensor<2, 3>& isochoric_stress) const {
  if (!(dt > 0) || !std::isfinite(dt)) {
    std::ostringstream message;
    message << region_text(name()) << " (visco-hyperelastic): time step dt = " << dt
            << " s is out of range: allowed (0, inf)";
    throw std::invalid_argument(message.str());
  }
  StressTangent iso;
  base_->evaluate(F, false, iso);
  isochoric_stress = iso.second_piola;
  if (include_volumetric)
    base_->evaluate(F, true, out);
  else
    out = iso;
  // Q^{n+1} = sum_i e_i Q_i^n + beta_i gamma_i (S_iso - S_iso^n); g - 1 = sum_i beta_i gamma_i.
  dealii::SymmetricTensor<2, 3> Q;
  double g1 = 0;
  for (unsigned int i = 0; i < n_branches(); ++i) {
    double decay = 0, gamma = 0;
    step_factors(i, dt, decay, gamma);
    const double bg = branches_[i].beta * gamma;
    g1 += bg;
    Q += decay * state.overstress[i] + bg * (isochoric_stress - state.isochoric_stress);
  }
  // A += (g - 1) (A_iso - delta_ik S_iso_JL) + delta_ik Q_JL: the isochoric material tangent
  // scaled by g and the overstress's geometric term.
  for (unsigned int i = 0; i < 3; ++i)
    for (unsigned int J = 0; J < 3; ++J)
      for (unsigned int k = 0; k < 3; ++k)
        for (unsigned int L = 0; L < 3; ++L) {
          double value = g1 * iso.tangent[i][J][k][L];
          if (i == k)
            value += Q[J][L] - g1 * isochoric_stress[J][L];
          out.tangent[i][J][k][L] += value;
        }
  out.second_piola += Q;
  out.first_piola += F * dealii::Tensor<2, 3>(Q);
}

double ViscoHyperelasticLaw::commit(double dt,
                                    const dealii::SymmetricTensor<2, 3>& isochoric_stress_old,
                                    const dealii::SymmetricTensor<2, 3>& isochoric_stress_new,
                                    dealii::SymmetricTensor<2, 3>* overstress) const {
  const dealii::SymmetricTensor<2, 3> change = isochoric_stress_new - isochoric_stress_old;
  const double two_mu = 2.0 * base_->small_strain_shear_modulus();
  double dissipation = 0;
  for (unsigned int i = 0; i < n_branches(); ++i) {
    const double beta = branches_[i].beta;
    double decay = 0, gamma = 0;
    step_factors(i, dt, decay, gamma);
    if (beta > 0) { // Q(s) = a E + c (1 - E) / x with a = Q_i^n, c = beta_i dS_iso
      double w_aa = 0, w_ac = 0, w_cc = 0;
      ViscoelasticMaterial::dissipation_weights(dt / branches_[i].relaxation_time, w_aa, w_ac,
                                                w_cc);
      const dealii::SymmetricTensor<2, 3>& a = overstress[i];
      dissipation +=
          (w_aa * (a * a) / beta + w_ac * (a * change) + w_cc * beta * (change * change)) / two_mu;
    }
    overstress[i] = decay * overstress[i] + beta * gamma * change;
  }
  return dissipation;
}

std::vector<ViscousBranchSpec> split_viscous_branches(const MaterialSpec& spec,
                                                      MaterialSpec& elastic) {
  elastic = spec;
  elastic.values.clear();
  std::map<unsigned int, std::map<std::string, double>> by_branch;
  for (const auto& [key, value] : spec.values) {
    const auto [stem, index] = split_key(key);
    if (index > 0 && (stem == "beta" || stem == "G" || stem == "tau"))
      by_branch[index][stem] = value;
    else
      elastic.values[key] = value;
  }
  std::vector<ViscousBranchSpec> branches;
  unsigned int expected = 1;
  const std::string where = region_text(spec.region) + " (law " + spec.law + ")";
  for (const auto& [index, values] : by_branch) {
    const std::string i = std::to_string(index);
    if (index != expected)
      throw std::invalid_argument(where + ": viscous branch " + std::to_string(expected) +
                                  " is missing (branches are numbered 1..N without gaps; "
                                  "found branch " +
                                  i + ")");
    ++expected;
    if (!values.count("tau"))
      throw std::invalid_argument(where + ": viscous branch " + i + " has no relaxation time tau" +
                                  i);
    if (values.count("beta") == values.count("G"))
      throw std::invalid_argument(where + ": viscous branch " + i + " needs exactly one of beta" +
                                  i + " (factor) and G" + i + " (Pa)");
    ViscousBranchSpec branch;
    branch.shear_modulus_given = values.count("G") > 0;
    branch.value = branch.shear_modulus_given ? values.at("G") : values.at("beta");
    branch.relaxation_time = values.at("tau");
    if (!(branch.value >= 0) || !std::isfinite(branch.value))
      out_of_range(where, (branch.shear_modulus_given ? "G" : "beta") + i, branch.value,
                   branch.shear_modulus_given ? "[0, inf) Pa" : "[0, inf)");
    if (!(branch.relaxation_time > 0) || !std::isfinite(branch.relaxation_time))
      out_of_range(where, "tau" + i, branch.relaxation_time, "(0, inf) s");
    branches.push_back(branch);
  }
  return branches;
}

std::vector<ViscousBranch> make_viscous_branches(const std::vector<ViscousBranchSpec>& specs,
                                                 const HyperelasticLaw& base) {
  std::vector<ViscousBranch> branches;
  const double mu = base.small_strain_shear_modulus();
  for (const ViscousBranchSpec& spec : specs)
    branches.push_back(
        {spec.shear_modulus_given ? spec.value / mu : spec.value, spec.relaxation_time});
  return branches;
}

} // namespace plantar::fem
