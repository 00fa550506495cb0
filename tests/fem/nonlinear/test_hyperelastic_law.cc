// Material-point checks of the hyperelastic laws (fem/hyperelastic_law.h):
//  - zero stress at F = I;
//  - P = dW/dF and A = dP/dF against central finite differences (relative 1e-6);
//  - the tangent at F = I equals LinearElasticMaterial's C (same E, nu) to 1e-6;
//  - the scene-text registry builds the laws and rejects bad input.
#include "fem/hyperelastic_material_table.h"
#include "fem/linear_elastic_material.h"

#include <gtest/gtest.h>

#include <cstdio>
#include <memory>
#include <random>

namespace plantar::fem {
namespace {

std::vector<std::unique_ptr<HyperelasticLaw>> laws() {
  std::vector<std::unique_ptr<HyperelasticLaw>> result;
  result.push_back(std::make_unique<NeoHookeanLaw>(NeoHookeanLaw::from_youngs(4e6, 0.45, "nh")));
  result.push_back(std::make_unique<MooneyRivlinLaw>(0.6e6, 0.15e6, 40e6, "mr"));
  return result;
}

dealii::Tensor<2, 3> random_deformation(std::mt19937& rng, double amplitude) {
  std::uniform_real_distribution<double> dist(-amplitude, amplitude);
  dealii::Tensor<2, 3> F;
  for (unsigned int i = 0; i < 3; ++i)
    for (unsigned int j = 0; j < 3; ++j)
      F[i][j] = (i == j ? 1.0 : 0.0) + dist(rng);
  return F;
}

TEST(HyperelasticLaw, ZeroStressAtIdentity) {
  for (const auto& law : laws()) {
    StressTangent st;
    law->evaluate(dealii::unit_symmetric_tensor<3>(), true, st);
    const double scale = law->small_strain_shear_modulus();
    std::printf("%s: |P(I)| = %.3e Pa, W(I) = %.3e (shear modulus %.3e Pa)\n",
                law->law_name().c_str(), st.first_piola.norm(),
                law->strain_energy(dealii::unit_symmetric_tensor<3>()), scale);
    EXPECT_LT(st.first_piola.norm(), 1e-12 * scale);
    EXPECT_LT(std::abs(law->strain_energy(dealii::unit_symmetric_tensor<3>())), 1e-12 * scale);
  }
}

TEST(HyperelasticLaw, StressAndTangentAgainstFiniteDifferences) {
  std::mt19937 rng(7);
  for (const auto& law : laws())
    for (int sample = 0; sample < 5; ++sample) {
      const dealii::Tensor<2, 3> F = random_deformation(rng, 0.3);
      StressTangent st;
      law->evaluate(F, true, st);
      const double h = 1e-6;
      double max_p_error = 0, max_a_error = 0;
      for (unsigned int k = 0; k < 3; ++k)
        for (unsigned int L = 0; L < 3; ++L) {
          dealii::Tensor<2, 3> Fp = F, Fm = F;
          Fp[k][L] += h;
          Fm[k][L] -= h;
          const double dW = (law->strain_energy(Fp) - law->strain_energy(Fm)) / (2 * h);
          max_p_error = std::max(max_p_error, std::abs(dW - st.first_piola[k][L]));
          StressTangent sp, sm;
          law->evaluate(Fp, true, sp);
          law->evaluate(Fm, true, sm);
          const dealii::Tensor<2, 3> dP = (sp.first_piola - sm.first_piola) / (2 * h);
          for (unsigned int i = 0; i < 3; ++i)
            for (unsigned int J = 0; J < 3; ++J)
              max_a_error = std::max(max_a_error, std::abs(dP[i][J] - st.tangent[i][J][k][L]));
        }
      const double p_rel = max_p_error / st.first_piola.norm();
      const double a_rel = max_a_error / st.tangent.norm();
      std::printf("%s det F = %.3f: P vs dW/dF rel %.2e, A vs dP/dF rel %.2e (tol 1e-6)\n",
                  law->law_name().c_str(), dealii::determinant(F), p_rel, a_rel);
      EXPECT_LT(p_rel, 1e-6);
      EXPECT_LT(a_rel, 1e-6);
    }
}

TEST(HyperelasticLaw, SmallStrainMatchesLinearElasticity) {
  for (const auto& law : laws()) {
    const LinearElasticMaterial linear(law->small_strain_youngs_modulus(),
                                       law->small_strain_poisson_ratio());
    StressTangent st;
    law->evaluate(dealii::unit_symmetric_tensor<3>(), true, st);
    double max_error = 0, max_value = 0;
    const auto& C = linear.stiffness();
    for (unsigned int i = 0; i < 3; ++i)
      for (unsigned int j = 0; j < 3; ++j)
        for (unsigned int k = 0; k < 3; ++k)
          for (unsigned int l = 0; l < 3; ++l) {
            max_error = std::max(max_error, std::abs(st.tangent[i][j][k][l] - C[i][j][k][l]));
            max_value = std::max(max_value, std::abs(C[i][j][k][l]));
          }
    // And the stress at a small strain: P(I + eps) vs C : eps.
    dealii::SymmetricTensor<2, 3> eps;
    eps[0][0] = 1e-7, eps[1][1] = -3e-8, eps[0][2] = 5e-8, eps[1][2] = 2e-8;
    dealii::Tensor<2, 3> F = dealii::unit_symmetric_tensor<3>();
    F += dealii::Tensor<2, 3>(eps);
    law->evaluate(F, true, st);
    const auto sigma = linear.stress(eps);
    const double stress_error =
        (dealii::Tensor<2, 3>(sigma) - st.first_piola).norm() / sigma.norm();
    std::printf("%s E = %.4e, nu = %.5f: max |A(I) - C| / max |C| = %.2e, stress at eps=1e-7 "
                "rel %.2e (tol 1e-6)\n",
                law->law_name().c_str(), law->small_strain_youngs_modulus(),
                law->small_strain_poisson_ratio(), max_error / max_value, stress_error);
    EXPECT_LT(max_error / max_value, 1e-6);
    EXPECT_LT(stress_error, 1e-6);
  }
  const NeoHookeanLaw nh = NeoHookeanLaw::from_youngs(4e6, 0.4999);
  EXPECT_NEAR(nh.small_strain_youngs_modulus() / 4e6, 1.0, 1e-12);
  EXPECT_NEAR(nh.small_strain_poisson_ratio(), 0.4999, 1e-12);
}

TEST(HyperelasticLaw, RegistryFromSceneText) {
  const auto specs = parse_material_specs(
      "a: law=neo_hookean, E=4e6, nu=0.45; b: law=mooney_rivlin, C10=0.5e6, C01=0.1e6, nu=0.49; "
      "c: law=neo_hookean, mu=1e6, kappa=5e7",
      "materials");
  const auto a = make_hyperelastic_law(specs.at("a"));
  const auto b = make_hyperelastic_law(specs.at("b"));
  const auto c = make_hyperelastic_law(specs.at("c"));
  std::printf("a: %s E=%.4e nu=%.4f; b: %s E=%.4e nu=%.4f; c: mu=%.4e kappa=%.4e\n",
              a->law_name().c_str(), a->small_strain_youngs_modulus(),
              a->small_strain_poisson_ratio(), b->law_name().c_str(),
              b->small_strain_youngs_modulus(), b->small_strain_poisson_ratio(),
              c->small_strain_shear_modulus(), c->bulk_modulus());
  EXPECT_NEAR(a->small_strain_youngs_modulus(), 4e6, 1e-6);
  EXPECT_NEAR(a->small_strain_poisson_ratio(), 0.45, 1e-12);
  EXPECT_NEAR(b->small_strain_shear_modulus(), 1.2e6, 1e-6);
  EXPECT_NEAR(b->small_strain_poisson_ratio(), 0.49, 1e-12);
  EXPECT_NEAR(c->bulk_modulus(), 5e7, 1e-6);

  const auto bad = parse_material_specs(
      "x: law=neo_hookean, E=4e6, nu=0.5; y: law=neo_hookean, E=4e6; z: law=ogden, mu=1; "
      "w: law=mooney_rivlin, C10=1e6, C01=0, kappa=1e8, E=3",
      "materials");
  for (const auto& [name, spec] : bad) {
    try {
      make_hyperelastic_law(spec);
      ADD_FAILURE() << "no exception for " << name;
    } catch (const std::invalid_argument& e) {
      std::printf("bad input %s -> %s\n", name.c_str(), e.what());
      EXPECT_NE(std::string(e.what()).find("'" + name + "'"), std::string::npos);
    }
  }
  // A new law registers itself under its name.
  register_hyperelastic_law("test_law", [](const MaterialSpec& spec) {
    return std::make_unique<NeoHookeanLaw>(spec.values.at("G"), spec.values.at("G") * 100,
                                           spec.region);
  });
  MaterialSpec custom{"r", "test_law", {{"G", 2.0}}};
  EXPECT_DOUBLE_EQ(make_hyperelastic_law(custom)->small_strain_shear_modulus(), 2.0);
}

} // namespace
} // namespace plantar::fem
