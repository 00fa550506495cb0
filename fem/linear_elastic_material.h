#pragma once
// Isotropic linear elasticity (Hooke's law), sigma = lambda tr(eps) I + 2 mu eps.

#include <deal.II/base/symmetric_tensor.h>

#include <string>

namespace plantar::fem {

class LinearElasticMaterial {
public:
  /// @param youngs_modulus E in Pa, E > 0.
  /// @param poisson_ratio nu, -1 < nu < 0.5.
  /// @param name region name used in error messages.
  /// @throws std::invalid_argument naming the region, parameter, value and range.
  LinearElasticMaterial(double youngs_modulus, double poisson_ratio, const std::string& name = "");

  double youngs_modulus() const { return youngs_modulus_; } ///< E, Pa
  double poisson_ratio() const { return poisson_ratio_; }   ///< nu
  double lambda() const { return lambda_; }                 ///< E nu / ((1 + nu)(1 - 2 nu)), Pa
  double mu() const { return mu_; }                         ///< shear modulus E / (2 (1 + nu)), Pa
  double bulk_modulus() const { return lambda_ + 2.0 * mu_ / 3.0; } ///< K, Pa

  /// The elasticity tensor C (3x3x3x3 symmetric, Pa): sigma = C : eps.
  const dealii::SymmetricTensor<4, 3>& stiffness() const { return stiffness_; }
  /// Cauchy stress (Pa) for the small strain @p strain.
  dealii::SymmetricTensor<2, 3> stress(const dealii::SymmetricTensor<2, 3>& strain) const {
    return stiffness_ * strain;
  }

private:
  double youngs_modulus_, poisson_ratio_, lambda_, mu_;
  dealii::SymmetricTensor<4, 3> stiffness_;
};

/// von Mises equivalent stress sqrt(3/2 s:s), s the deviator of @p stress (Pa).
double von_mises(const dealii::SymmetricTensor<2, 3>& stress);

} // namespace plantar::fem
