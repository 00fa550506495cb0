#pragma once
// Hyperelastic material laws in a total Lagrangian setting (deal.II step-44
// structure: the law is a class apart from the Newton solver).
//
// Every law here is decoupled into an isochoric and a volumetric part,
//   W(F) = W_iso(I1_bar, I2_bar) + U(J),
//   J = det F,  C = F^T F,  I1_bar = J^(-2/3) tr C,
//   I2_bar = J^(-4/3) (tr(C)^2 - tr(C^2)) / 2,
// with U(J) = kappa / 4 (J^2 - 1 - 2 ln J) (Simo-Taylor; step-44's G(J)),
// U'(1) = 0, U''(1) = kappa. A new law is one class deriving from
// HyperelasticLaw that returns W_iso and its first and second partial
// derivatives with respect to (I1_bar, I2_bar); the base class turns them into
// the second Piola-Kirchhoff stress S = 2 dW/dC (Pa), the first
// Piola-Kirchhoff stress P = F S (Pa) and the consistent tangent
// A = dP/dF (Pa), A_iJkL = delta_ik S_JL + F_iI F_kK CC_IJKL with the material
// tangent CC = 4 d^2W/dC dC (Holzapfel, Nonlinear Solid Mechanics, 6.6).
// At F = I: S = 0 and A = the linear elasticity tensor with shear modulus
// small_strain_shear_modulus() and bulk modulus kappa.

#include <deal.II/base/symmetric_tensor.h>
#include <deal.II/base/tensor.h>

#include <string>

namespace plantar::fem {

/// W_iso and its partial derivatives with respect to (I1_bar, I2_bar) (Pa).
struct IsochoricEnergy {
  double energy = 0;                ///< W_iso, J/m^3
  double d1 = 0, d2 = 0;            ///< dW/dI1_bar, dW/dI2_bar
  double d11 = 0, d22 = 0, d12 = 0; ///< second derivatives
};

/// Stress and tangent of a law at one deformation gradient.
struct StressTangent {
  dealii::Tensor<2, 3> first_piola;           ///< P, Pa
  dealii::SymmetricTensor<2, 3> second_piola; ///< S, Pa
  dealii::Tensor<4, 3> tangent;               ///< A = dP/dF, Pa (A[i][J][k][L])
};

class HyperelasticLaw {
public:
  /// @param bulk_modulus kappa (Pa), > 0. @param name region name for messages.
  HyperelasticLaw(double bulk_modulus, std::string name);
  virtual ~HyperelasticLaw() = default;

  /// W_iso(I1_bar, I2_bar) and its derivatives. Implemented by each law.
  virtual IsochoricEnergy isochoric(double i1_bar, double i2_bar) const = 0;
  /// Shear modulus of the linearised law (Pa): mu = 2 (dW/dI1_bar + dW/dI2_bar) at 3, 3.
  virtual double small_strain_shear_modulus() const = 0;
  virtual std::string law_name() const = 0;

  double bulk_modulus() const { return kappa_; } ///< kappa, Pa
  /// Small-strain Young's modulus 9 K mu / (3 K + mu) (Pa) and Poisson ratio
  /// (3 K - 2 mu) / (2 (3 K + mu)).
  double small_strain_youngs_modulus() const;
  double small_strain_poisson_ratio() const;
  const std::string& name() const { return name_; }

  /// U(J), U'(J), U''(J) of kappa / 4 (J^2 - 1 - 2 ln J). J > 0.
  double volumetric_energy(double J) const;
  double volumetric_stress(double J) const;  ///< U'(J) = kappa / 2 (J - 1 / J), Pa
  double volumetric_tangent(double J) const; ///< U''(J) = kappa / 2 (1 + 1 / J^2), Pa

  /// W(F) (J/m^3). Throws std::runtime_error if det F <= 0.
  double strain_energy(const dealii::Tensor<2, 3>& F) const;
  /// P, S and A = dP/dF at @p F. If @p include_volumetric is false, only the
  /// isochoric part W_iso is differentiated (the mixed formulation adds the
  /// volumetric part through its own pressure). Throws std::runtime_error
  /// naming the region if det F <= 0 or the result is not finite.
  void evaluate(const dealii::Tensor<2, 3>& F, bool include_volumetric, StressTangent& out) const;

protected:
  double kappa_;
  std::string name_;
};

/// Compressible Neo-Hookean: W_iso = mu / 2 (I1_bar - 3).
class NeoHookeanLaw : public HyperelasticLaw {
public:
  /// @param shear_modulus mu (Pa) > 0; @param bulk_modulus kappa (Pa) > 0.
  NeoHookeanLaw(double shear_modulus, double bulk_modulus, const std::string& name = "");
  /// From the small-strain E (Pa, > 0) and nu (-1 < nu < 0.5).
  static NeoHookeanLaw from_youngs(double youngs_modulus, double poisson_ratio,
                                   const std::string& name = "");
  IsochoricEnergy isochoric(double i1_bar, double i2_bar) const override;
  double small_strain_shear_modulus() const override { return mu_; }
  std::string law_name() const override { return "neo_hookean"; }

private:
  double mu_;
};

/// Mooney-Rivlin: W_iso = C10 (I1_bar - 3) + C01 (I2_bar - 3); mu = 2 (C10 + C01).
class MooneyRivlinLaw : public HyperelasticLaw {
public:
  /// @param c10, c01 (Pa), c10 >= 0, c01 >= 0, c10 + c01 > 0; @param bulk_modulus kappa (Pa) > 0.
  MooneyRivlinLaw(double c10, double c01, double bulk_modulus, const std::string& name = "");
  IsochoricEnergy isochoric(double i1_bar, double i2_bar) const override;
  double small_strain_shear_modulus() const override { return 2 * (c10_ + c01_); }
  std::string law_name() const override { return "mooney_rivlin"; }

private:
  double c10_, c01_;
};

} // namespace plantar::fem
