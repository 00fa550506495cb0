#include "fem/linear_elastic_material.h"

#include <cmath>
#include <sstream>
#include <stdexcept>

namespace plantar::fem {

LinearElasticMaterial::LinearElasticMaterial(double youngs_modulus, double poisson_ratio,
                                             const std::string& name)
    : youngs_modulus_(youngs_modulus), poisson_ratio_(poisson_ratio) {
  const std::string where = name.empty() ? "" : " of material '" + name + "'";
  if (!(youngs_modulus > 0.0) || !std::isfinite(youngs_modulus)) {
    std::ostringstream msg;
    msg << "Young's modulus E" << where << " = " << youngs_modulus
        << " Pa is out of range: E must be > 0";
    throw std::invalid_argument(msg.str());
  }
  if (!(poisson_ratio > -1.0 && poisson_ratio < 0.5)) {
    std::ostringstream msg;
    msg << "Poisson ratio nu" << where << " = " << poisson_ratio
        << " is out of range: -1 < nu < 0.5";
    throw std::invalid_argument(msg.str());
  }
  lambda_ = youngs_modulus * poisson_ratio / ((1.0 + poisson_ratio) * (1.0 - 2.0 * poisson_ratio));
  mu_ = youngs_modulus / (2.0 * (1.0 + poisson_ratio));
  const auto identity = dealii::unit_symmetric_tensor<3>();
  stiffness_ = lambda_ * dealii::outer_product(identity, identity) +
               2.0 * mu_ * dealii::identity_tensor<3>();
}

double von_mises(const dealii::SymmetricTensor<2, 3>& stress) {
  const auto deviator = dealii::deviator(stress);
  return std::sqrt(1.5 * dealii::scalar_product(deviator, deviator));
}

} // namespace plantar::fem
