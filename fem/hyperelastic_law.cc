#include "fem/hyperelastic_law.h"

#include <cmath>
#include <sstream>
#include <stdexcept>

namespace plantar::fem {
namespace {

std::string region_text(const std::string& name) {
  return name.empty() ? std::string("material") : "material region '" + name + "'";
}

void require_positive(double value, const char* parameter, const std::string& name) {
  if (!(value > 0) || !std::isfinite(value)) {
    std::ostringstream message;
    message << region_text(name) << ": " << parameter << " = " << value
            << " is out of range: allowed (0, inf)";
    throw std::invalid_argument(message.str());
  }
}

} // namespace

HyperelasticLaw::HyperelasticLaw(double bulk_modulus, std::string name)
    : kappa_(bulk_modulus), name_(std::move(name)) {
  require_positive(bulk_modulus, "kappa", name_);
}

double HyperelasticLaw::small_strain_youngs_modulus() const {
  const double mu = small_strain_shear_modulus();
  return 9 * kappa_ * mu / (3 * kappa_ + mu);
}

double HyperelasticLaw::small_strain_poisson_ratio() const {
  const double mu = small_strain_shear_modulus();
  return (3 * kappa_ - 2 * mu) / (2 * (3 * kappa_ + mu));
}

double HyperelasticLaw::volumetric_energy(double J) const {
  return 0.25 * kappa_ * (J * J - 1 - 2 * std::log(J));
}
double HyperelasticLaw::volumetric_stress(double J) const {
  return 0.5 * kappa_ * (J - 1 / J);
}
double HyperelasticLaw::volumetric_tangent(double J) const {
  return 0.5 * kappa_ * (1 + 1 / (J * J));
}

double HyperelasticLaw::strain_energy(const dealii::Tensor<2, 3>& F) const {
  const double J = dealii::determinant(F);
  if (!(J > 0))
    throw std::runtime_error(region_text(name_) + ": det F = " + std::to_string(J) +
                             " is out of range: allowed (0, inf)");
  const dealii::Tensor<2, 3> C = dealii::transpose(F) * F;
  const double i1 = dealii::trace(C);
  const double i2 = 0.5 * (i1 * i1 - dealii::double_contract<0, 0, 1, 1>(C, C));
  const double i3 = J * J;
  return isochoric(i1 * std::pow(i3, -1.0 / 3), i2 * std::pow(i3, -2.0 / 3)).energy +
         volumetric_energy(J);
}

void HyperelasticLaw::evaluate(const dealii::Tensor<2, 3>& F, bool include_volumetric,
                               StressTangent& out) const {
  const double J = dealii::determinant(F);
  if (!(J > 0))
    throw std::runtime_error(region_text(name_) + ": det F = " + std::to_string(J) +
                             " is out of range: allowed (0, inf) (element inverted)");
  dealii::Tensor<2, 3> C = dealii::transpose(F) * F;
  const dealii::Tensor<2, 3> C_inv = dealii::invert(C);
  const double i1 = dealii::trace(C);
  const double i2 = 0.5 * (i1 * i1 - dealii::double_contract<0, 0, 1, 1>(C, C));
  const double i3 = J * J;
  const double p13 = std::pow(i3, -1.0 / 3), p23 = p13 * p13;
  const IsochoricEnergy w = isochoric(i1 * p13, i2 * p23);

  // Chain rule from (I1_bar, I2_bar, J) to (I1, I2, I3).
  const double a1 = p13, a3 = -i1 * p13 / (3 * i3);
  const double b2 = p23, b3 = -2 * i2 * p23 / (3 * i3);
  const double a13 = -p13 / (3 * i3), a33 = 4 * i1 * p13 / (9 * i3 * i3);
  const double b23 = -2 * p23 / (3 * i3), b33 = 10 * i2 * p23 / (9 * i3 * i3);
  double W[3] = {w.d1 * a1, w.d2 * b2, w.d1 * a3 + w.d2 * b3};
  const double da[3] = {a1, 0, a3}, db[3] = {0, b2, b3};
  double WW[3][3];
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j)
      WW[i][j] =
          w.d11 * da[i] * da[j] + w.d22 * db[i] * db[j] + w.d12 * (da[i] * db[j] + db[i] * da[j]);
  WW[0][2] += w.d1 * a13;
  WW[2][0] += w.d1 * a13;
  WW[2][2] += w.d1 * a33 + w.d2 * b33;
  WW[1][2] += w.d2 * b23;
  WW[2][1] += w.d2 * b23;
  if (include_volumetric) {
    const double j3 = 0.5 / J, j33 = -0.25 / (J * i3);
    W[2] += volumetric_stress(J) * j3;
    WW[2][2] += volumetric_tangent(J) * j3 * j3 + volumetric_stress(J) * j33;
  }

  // G_1 = I, G_2 = I1 I - C, G_3 = I3 C^-1 (derivatives of the invariants).
  dealii::Tensor<2, 3> G[3];
  for (int I = 0; I < 3; ++I)
    for (int J2 = 0; J2 < 3; ++J2) {
      const double delta = (I == J2) ? 1.0 : 0.0;
      G[0][I][J2] = delta;
      G[1][I][J2] = i1 * delta - C[I][J2];
      G[2][I][J2] = i3 * C_inv[I][J2];
    }
  dealii::Tensor<2, 3> S;
  for (int a = 0; a < 3; ++a)
    S += 2 * W[a] * G[a];

  dealii::Tensor<4, 3> CC;
  for (int I = 0; I < 3; ++I)
    for (int J2 = 0; J2 < 3; ++J2)
      for (int K = 0; K < 3; ++K)
        for (int L = 0; L < 3; ++L) {
          double value = 0;
          for (int a = 0; a < 3; ++a)
            for (int b = 0; b < 3; ++b)
              value += WW[a][b] * G[a][I][J2] * G[b][K][L];
          const double dIJ = I == J2, dKL = K == L, dIK = I == K, dJL = J2 == L, dIL = I == L,
                       dJK = J2 == K;
          value += W[1] * (dIJ * dKL - 0.5 * (dIK * dJL + dIL * dJK));
          value += W[2] * i3 *
                   (C_inv[I][J2] * C_inv[K][L] -
                    0.5 * (C_inv[I][K] * C_inv[J2][L] + C_inv[I][L] * C_inv[J2][K]));
          CC[I][J2][K][L] = 4 * value;
        }

  // A_iJkL = delta_ik S_JL + F_iI F_kN CC_IJLN.
  dealii::Tensor<4, 3> FC; // FC[i][J][L][N] = F_iI CC_IJLN
  for (int i = 0; i < 3; ++i)
    for (int J2 = 0; J2 < 3; ++J2)
      for (int L = 0; L < 3; ++L)
        for (int N = 0; N < 3; ++N) {
          double value = 0;
          for (int I = 0; I < 3; ++I)
            value += F[i][I] * CC[I][J2][L][N];
          FC[i][J2][L][N] = value;
        }
  for (int i = 0; i < 3; ++i)
    for (int J2 = 0; J2 < 3; ++J2)
      for (int k = 0; k < 3; ++k)
        for (int L = 0; L < 3; ++L) {
          double value = (i == k) ? S[J2][L] : 0.0;
          for (int N = 0; N < 3; ++N)
            value += FC[i][J2][L][N] * F[k][N];
          out.tangent[i][J2][k][L] = value;
        }
  out.first_piola = F * S;
  out.second_piola = dealii::symmetrize(S);
  if (!std::isfinite(out.first_piola.norm()) || !std::isfinite(out.tangent.norm()))
    throw std::runtime_error(region_text(name_) + ": stress or tangent is not finite (det F = " +
                             std::to_string(J) + ")");
}

NeoHookeanLaw::NeoHookeanLaw(double shear_modulus, double bulk_modulus, const std::string& name)
    : HyperelasticLaw(bulk_modulus, name), mu_(shear_modulus) {
  require_positive(shear_modulus, "mu", name);
}

NeoHookeanLaw NeoHookeanLaw::from_youngs(double youngs_modulus, double poisson_ratio,
                                         const std::string& name) {
  require_positive(youngs_modulus, "E", name);
  if (!(poisson_ratio > -1 && poisson_ratio < 0.5)) {
    std::ostringstream message;
    message << region_text(name) << ": nu = " << poisson_ratio
            << " is out of range: allowed (-1, 0.5)";
    throw std::invalid_argument(message.str());
  }
  const double mu = youngs_modulus / (2 * (1 + poisson_ratio));
  const double kappa = youngs_modulus / (3 * (1 - 2 * poisson_ratio));
  return NeoHookeanLaw(mu, kappa, name);
}

IsochoricEnergy NeoHookeanLaw::isochoric(double i1_bar, double /*i2_bar*/) const {
  IsochoricEnergy w;
  w.energy = 0.5 * mu_ * (i1_bar - 3);
  w.d1 = 0.5 * mu_;
  return w;
}

MooneyRivlinLaw::MooneyRivlinLaw(double c10, double c01, double bulk_modulus,
                                 const std::string& name)
    : HyperelasticLaw(bulk_modulus, name), c10_(c10), c01_(c01) {
  if (!(c10 >= 0) || !(c01 >= 0) || !(c10 + c01 > 0) || !std::isfinite(c10 + c01)) {
    std::ostringstream message;
    message << region_text(name) << ": C10 = " << c10 << ", C01 = " << c01
            << " are out of range: allowed C10 >= 0, C01 >= 0, C10 + C01 > 0";
    throw std::invalid_argument(message.str());
  }
}

IsochoricEnergy MooneyRivlinLaw::isochoric(double i1_bar, double i2_bar) const {
  IsochoricEnergy w;
  w.energy = c10_ * (i1_bar - 3) + c01_ * (i2_bar - 3);
  w.d1 = c10_;
  w.d2 = c01_;
  return w;
}

} // namespace plantar::fem
