#pragma once
// Finite-strain visco-hyperelasticity (Simo 1987; Holzapfel, Nonlinear Solid Mechanics, 6.10):
// relaxing isochoric overstresses Q_i over a hyperelastic base law (fem/hyperelastic_law.h),
//
//   S = S_vol(J) + S_iso(C) + sum_i Q_i,   dQ_i/dt + Q_i / tau_i = beta_i dS_iso/dt,
//
// S_iso = 2 dW_iso/dC of the base law (the long-term, equilibrium response), beta_i >= 0 the
// free-energy factor of branch i (dimensionless), tau_i > 0 its relaxation time (s). Under a
// step in C held afterwards S_iso relaxes as S_iso (1 + sum_i beta_i exp(-t/tau_i)): at small
// strain the linear Prony law (fem/viscoelastic_material.h) with G_i = beta_i mu, K_i = 0.
//
// Over a step dt the overstress is advanced by the exponential update exact when S_iso is
// linear in time over the step (the form of the linear Prony law, not Holzapfel's midpoint
// factor exp(-dt/(2 tau_i))), unconditionally stable for any dt / tau_i:
//
//   Q_i^{n+1} = e_i Q_i^n + beta_i gamma_i (S_iso^{n+1} - S_iso^n),
//   e_i = exp(-dt/tau_i),  gamma_i = (tau_i/dt)(1 - e_i)  in (0, 1].
//
// Consistent algorithmic tangent (the material tangent of S^{n+1} at fixed history):
//   CC = CC_vol + g CC_iso,  g = 1 + sum_i beta_i gamma_i,
// and A = dP/dF, P = F S: A_iJkL = delta_ik S_JL + F_iI F_kK CC_IJKL.
//
// The law is constant (Model); the state per quadrature point (S_iso^n and the Q_i^n) lives
// apart (fem/visco_hyperelastic_history.h, Data).
//
// Scene syntax (Sole/Materials, the hyperelastic laws' keys plus branches, as law=prony numbers
// them): "rubber: law=neo_hookean, E=2e6, nu=0.45, beta1=1.5, tau1=1e-3, G2=2e5, tau2=0.1"
//   branch i = 1..N without gaps: tau<i> (s, > 0) and either beta<i> (>= 0) or G<i> (Pa, >= 0,
//   the branch's small-strain shear modulus: beta_i = G_i / mu, mu the base law's small-strain
//   shear modulus). The base law's E, nu (or mu, kappa, or C10, C01, ...) are the long-term ones.

#include "fem/hyperelastic_law.h"
#include "fem/material_table.h"

#include <deal.II/base/symmetric_tensor.h>
#include <deal.II/base/tensor.h>

#include <memory>
#include <string>
#include <vector>

namespace plantar::fem {

/// One relaxing isochoric branch.
struct ViscousBranch {
  double beta = 0;            ///< free-energy factor beta_i >= 0 (dimensionless)
  double relaxation_time = 1; ///< tau_i > 0, s
};

/// The committed state of one quadrature point, read by ViscoHyperelasticLaw::evaluate.
struct ViscoPointState {
  const dealii::SymmetricTensor<2, 3>* overstress = nullptr; ///< Q_i^n, n_branches of them, Pa
  dealii::SymmetricTensor<2, 3> isochoric_stress;            ///< S_iso^n, Pa
};

class ViscoHyperelasticLaw {
public:
  /// @param base the long-term hyperelastic law (not null); @param branches any number.
  /// @throws std::invalid_argument naming the region, the parameter (beta<i>, tau<i>), its value
  ///   and the allowed range (beta_i < 0, tau_i <= 0, non-finite).
  ViscoHyperelasticLaw(std::shared_ptr<const HyperelasticLaw> base,
                       std::vector<ViscousBranch> branches);

  const HyperelasticLaw& base() const { return *base_; }
  const std::shared_ptr<const HyperelasticLaw>& base_pointer() const { return base_; }
  const std::vector<ViscousBranch>& branches() const { return branches_; }
  unsigned int n_branches() const { return static_cast<unsigned int>(branches_.size()); }
  const std::string& name() const { return base_->name(); }
  /// mu_0 = mu (1 + sum_i beta_i) (Pa): the small-strain shear modulus at t = 0+.
  double instantaneous_shear_modulus() const;

  /// e_i = exp(-dt/tau_i), gamma_i = (tau_i/dt)(1 - e_i) of branch @p i, dt > 0 (s).
  void step_factors(unsigned int i, double dt, double& decay, double& gamma) const;

  /// Algorithmic stress and consistent tangent at the end of a step of length @p dt (s) from
  /// the committed state @p state, at deformation gradient @p F: out = (P, S, A) with
  /// S = S_base + sum_i Q_i^{n+1}. If @p include_volumetric is false, S_base = S_iso (the mixed
  /// formulation adds the volumetric part). @p isochoric_stress receives S_iso(F) (Pa), the
  /// value commit() needs. Throws as HyperelasticLaw::evaluate. No heap allocation.
  void evaluate(const dealii::Tensor<2, 3>& F, bool include_volumetric, double dt,
                const ViscoPointState& state, StressTangent& out,
                dealii::SymmetricTensor<2, 3>& isochoric_stress) const;

  /// Q_i^{n+1} = e_i Q_i^n + beta_i gamma_i (S_iso^{n+1} - S_iso^n) for every branch, in place
  /// on @p overstress (n_branches tensors, Pa). Returns the energy the dashpots dissipated over
  /// the step per unit reference volume (J/m^3),
  ///   sum_i int_0^dt Q_i : Q_i / (2 beta_i mu tau_i) ds,
  /// mu the base law's small-strain shear modulus, integrated in closed form for S_iso linear in
  /// time (ViscoelasticMaterial::dissipation_weights): the linear Prony law's dissipation
  /// h_i : C_i^-1 : h_i / tau_i with G_i = beta_i mu, K_i = 0, so exact at small strain; at
  /// finite strain the same measure of the overstresses (not a derived dissipation inequality).
  double commit(double dt, const dealii::SymmetricTensor<2, 3>& isochoric_stress_old,
                const dealii::SymmetricTensor<2, 3>& isochoric_stress_new,
                dealii::SymmetricTensor<2, 3>* overstress) const;

private:
  std::shared_ptr<const HyperelasticLaw> base_;
  std::vector<ViscousBranch> branches_;
};

/// One branch as written in a scene.
struct ViscousBranchSpec {
  bool shear_modulus_given = false; ///< G<i> given (Pa) rather than beta<i>
  double value = 0;                 ///< beta_i or G_i
  double relaxation_time = 0;       ///< tau_i, s
};

/// Splits the branch keys (beta<i>, G<i>, tau<i>) off @p spec: returns @p spec without them in
/// @p elastic and the branches' raw values. Throws std::invalid_argument naming the region, the
/// key, its value and the allowed range (gaps in the numbering, a branch without tau<i>, with
/// both or neither of beta<i> and G<i>, negative or non-finite values).
std::vector<ViscousBranchSpec> split_viscous_branches(const MaterialSpec& spec,
                                                      MaterialSpec& elastic);

/// The branches of @p specs for the base law @p base (G<i> -> beta_i = G_i / mu).
std::vector<ViscousBranch> make_viscous_branches(const std::vector<ViscousBranchSpec>& specs,
                                                 const HyperelasticLaw& base);

} // namespace plantar::fem
