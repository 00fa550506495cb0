#pragma once
// Isotropic linear viscoelasticity, generalized Maxwell (Prony series), per material region:
//
//   G(t) = G_inf + sum_i G_i exp(-t / tau_i),   K(t) = K_inf + sum_i K_i exp(-t / tau_i),
//   sigma(t) = C_inf : eps(t) + sum_i h_i(t),   h_i(t) = int_0^t exp(-(t-s)/tau_i) C_i : deps/ds
//   ds, C = 3 K P_vol + 2 G P_dev  (P_vol = I x I / 3, P_dev = II - P_vol).
//
// A branch with K_i = 0 relaxes in shear only (elastic bulk). The internal variable h_i (a
// stress, Pa) is advanced over a step dt by the exponential recursive update (Simo and Hughes,
// Computational Inelasticity, ch. 10; Taylor, FEAP), exact for a strain linear in time over
// the step and unconditionally stable for any dt / tau_i:
//
//   h_i^{n+1} = e_i h_i^n + gamma_i C_i : (eps^{n+1} - eps^n),
//   e_i = exp(-dt/tau_i),  gamma_i = (tau_i/dt) (1 - e_i)  in (0, 1].
//
// Hence sigma^{n+1} = C_eff : eps^{n+1} + s^n with the step's constant effective tensor
// C_eff = C_inf + sum_i gamma_i C_i and the history stress s^n = sum_i (e_i h_i^n - gamma_i
// C_i : eps^n). Limits: dt -> 0 gives C_0 = C_inf + sum C_i, dt -> inf gives C_inf.
//
// In a scene (Sole/Materials, fem/material_table.h syntax), law=prony:
//   "rubber: law=prony, E=2e6, nu=0.45, E1=3e6, tau1=1e-3, E2=1e6, tau2=0.1"
//     E, nu the long-term modulus (Pa) and Poisson ratio; branch i: E<i> (Pa) relaxing shear and
//     bulk alike (branch Poisson ratio nu), or G<i> and optionally K<i> (Pa); tau<i> (s).
//   Or the long-term moduli as G, K (Pa) instead of E, nu. Branches are numbered 1..N.

#include "fem/material_table.h"

#include <deal.II/base/symmetric_tensor.h>

#include <map>
#include <string>
#include <vector>

namespace plantar::fem {

/// One Maxwell branch: moduli (Pa) released with relaxation time tau (s).
struct PronyBranch {
  double shear_modulus = 0;   ///< G_i >= 0, Pa
  double bulk_modulus = 0;    ///< K_i >= 0, Pa (0: the bulk is elastic in this branch)
  double relaxation_time = 1; ///< tau_i > 0, s
};

class ViscoelasticMaterial {
public:
  /// @param shear_modulus G_inf >= 0 (Pa); @param bulk_modulus K_inf > 0 (Pa);
  /// @param branches the Maxwell branches (any number, may be empty: elastic).
  /// @param name region name used in error messages.
  /// @throws std::invalid_argument naming the region, the parameter, its value and the allowed
  ///   range (G_inf < 0, K_inf <= 0, G_i < 0, K_i < 0, tau_i <= 0, non-finite, G_0 = 0).
  ViscoelasticMaterial(double shear_modulus, double bulk_modulus, std::vector<PronyBranch> branches,
                       const std::string& name = "");

  /// From a scene spec of law "linear" (E, nu) or "prony" (see above). Throws
  /// std::invalid_argument naming the region and the parameter.
  static ViscoelasticMaterial from_spec(const MaterialSpec& spec);

  const std::string& name() const { return name_; }
  double shear_modulus() const { return shear_modulus_; } ///< G_inf, Pa
  double bulk_modulus() const { return bulk_modulus_; }   ///< K_inf, Pa
  const std::vector<PronyBranch>& branches() const { return branches_; }
  unsigned int n_branches() const { return static_cast<unsigned int>(branches_.size()); }

  /// G(t) = G_inf + sum_i G_i exp(-t/tau_i) (Pa), t >= 0 s.
  double shear_relaxation(double t) const;
  /// K(t) = K_inf + sum_i K_i exp(-t/tau_i) (Pa), t >= 0 s.
  double bulk_relaxation(double t) const;

  /// 3 K P_vol + 2 G P_dev (Pa), the isotropic tensor of moduli G, K.
  static dealii::SymmetricTensor<4, 3> isotropic_stiffness(double shear, double bulk);
  /// C_inf (Pa).
  const dealii::SymmetricTensor<4, 3>& long_term_stiffness() const { return long_term_; }
  /// C_i of branch @p i (Pa).
  const dealii::SymmetricTensor<4, 3>& branch_stiffness(unsigned int i) const {
    return branch_stiffness_[i];
  }
  /// C_0 = C_inf + sum_i C_i (Pa), the instantaneous response.
  dealii::SymmetricTensor<4, 3> instantaneous_stiffness() const;
  /// C_eff(dt) = C_inf + sum_i gamma_i(dt) C_i (Pa), dt > 0 s.
  dealii::SymmetricTensor<4, 3> effective_stiffness(double dt) const;

  /// e = exp(-dt/tau) and gamma = (tau/dt)(1 - e), computed without cancellation for small
  /// dt/tau (expm1). dt > 0, tau > 0 (s).
  static void step_factors(double dt, double tau, double& decay, double& gamma);

  /// Weights of a branch's dissipation over one step of x = dt / tau (> 0): for the overstress
  /// h(s) = a E + c (1 - E) / x, E = exp(-s/tau) (the recursive update's, exact for a strain
  /// linear in time over the step), int_0^dt h : C_i^-1 : h / tau ds = w_aa m(a, a) +
  /// w_ac m(a, c) + w_cc m(c, c), m(x, y) = x : C_i^-1 : y. Dimensionless; no cancellation for
  /// small x.
  static void dissipation_weights(double x, double& w_aa, double& w_ac, double& w_cc);

private:
  std::string name_;
  double shear_modulus_, bulk_modulus_;
  std::vector<PronyBranch> branches_;
  dealii::SymmetricTensor<4, 3> long_term_;
  std::vector<dealii::SymmetricTensor<4, 3>> branch_stiffness_;
};

/// Viscoelastic materials indexed by deal.II material id (law "linear" gives no branch).
class ViscoelasticMaterialTable {
public:
  /// Resolves @p specs against the mesh's physical volumes, as MaterialTable does (every volume
  /// holding cells has a spec, every spec names a volume); laws "linear" and "prony".
  ViscoelasticMaterialTable(const std::map<std::string, MaterialSpec>& specs,
                            const PhysicalGroups& groups);
  /// Explicit id -> material (generated meshes, tests).
  explicit ViscoelasticMaterialTable(
      const std::map<dealii::types::material_id, ViscoelasticMaterial>& by_id);
  /// One material for every cell whatever its id.
  explicit ViscoelasticMaterialTable(const ViscoelasticMaterial& material);

  /// The material of cells with material id @p id (throws std::runtime_error if none).
  const ViscoelasticMaterial& operator[](dealii::types::material_id id) const;
  const std::map<dealii::types::material_id, ViscoelasticMaterial>& by_id() const { return by_id_; }

private:
  std::map<dealii::types::material_id, ViscoelasticMaterial> by_id_;
  bool uniform_ = false;
};

} // namespace plantar::fem
