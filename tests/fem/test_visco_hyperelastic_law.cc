// Finite-strain visco-hyperelastic law (fem/visco_hyperelastic_law.h, issue 24):
//  (a) the consistent tangent against central finite differences of the algorithmic stress at a
//      general F with nonzero history, dt / tau = 1e-3, 1, 1e3 (Neo-Hookean, Mooney-Rivlin);
//  (b) at small strain the law equals the linear Prony law (G_i = beta_i mu, K_i = 0) in a
//      relaxation test, to O(strain);
//  (c) relaxation under a finite uniaxial isochoric stretch (lambda = 1.5) against the closed
//      form: a step held, S = S_iso (1 + sum beta_i e^{-t/tau_i}); a ramp held, against the
//      hereditary integral by Gauss quadrature, for dt << tau (O(dt^2) by two dt), ~ tau, >> tau;
//  (d) the dashpots' dissipation (ViscoHyperelasticLaw::commit's return) in a simple-shear ramp
//      held afterwards, against the linear Maxwell branches' closed forms at the ramp's end and
//      after the hold, for one step, a few and many per ramp (exact for the linear law at any
//      dt: the strain is linear in time over each step), to O(strain^2) in simple shear;
//  and the scene syntax with its errors.
#include "fem/hyperelastic_material_table.h"
#include "fem/visco_hyperelastic_law.h"
#include "fem/viscoelastic_material.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <memory>
#include <vector>

namespace plantar::fem {
namespace {

using Sym = dealii::SymmetricTensor<2, 3>;
using Ten = dealii::Tensor<2, 3>;

// A law and one point's committed state, advanced step by step as a solver would.
struct Point {
  explicit Point(const ViscoHyperelasticLaw& l) : law(l), overstress(l.n_branches()) {}
  StressTangent step(const Ten& F, double dt, bool include_volumetric = true) {
    ViscoPointState state;
    state.overstress = overstress.data();
    state.isochoric_stress = isochoric;
    StressTangent out;
    law.evaluate(F, include_volumetric, dt, state, out, trial);
    return out;
  }
  /// Returns the step's dissipation (J/m^3).
  double commit(double dt) {
    const double dissipated = law.commit(dt, isochoric, trial, overstress.data());
    isochoric = trial;
    return dissipated;
  }
  const ViscoHyperelasticLaw& law;
  std::vector<Sym> overstress;
  Sym isochoric, trial;
};

Ten general_F(double scale) {
  Ten H;
  const double h[3][3] = {{0.3, 0.2, -0.1}, {0.05, -0.1, 0.15}, {-0.1, 0.12, 0.1}};
  for (unsigned int i = 0; i < 3; ++i)
    for (unsigned int j = 0; j < 3; ++j)
      H[i][j] = scale * h[i][j];
  return dealii::unit_symmetric_tensor<3>() + H;
}

TEST(ViscoHyperelasticLaw, TangentMatchesFiniteDifferences) {
  const std::vector<ViscousBranch> branches{{1.5, 1e-2}, {0.5, 1.0}};
  const std::vector<std::shared_ptr<const HyperelasticLaw>> bases{
      std::make_shared<NeoHookeanLaw>(1e6, 2e7, "nh"),
      std::make_shared<MooneyRivlinLaw>(3e5, 1e5, 2e7, "mr")};
  std::printf("\n%4s %10s %6s %12s %12s %12s\n", "law", "dt/tau1", "vol", "|Q|/|S_iso|", "|A|",
              "rel. err");
  for (const auto& base : bases) {
    const ViscoHyperelasticLaw law(base, branches);
    for (const double ratio : {1e-3, 1.0, 1e3}) {
      const double dt = ratio * branches[0].relaxation_time;
      for (const bool vol : {true, false}) {
        // History: two committed steps at other deformations.
        Point point(law);
        point.step(general_F(0.4), 1e-2);
        point.commit(1e-2);
        point.step(general_F(-0.7), 3e-3);
        point.commit(3e-3);
        Sym Q;
        for (const Sym& q : point.overstress)
          Q += q;
        const Ten F = general_F(1.0);
        const StressTangent exact = point.step(F, dt, vol);
        const double h = 1e-6;
        double max_err = 0;
        for (unsigned int k = 0; k < 3; ++k)
          for (unsigned int L = 0; L < 3; ++L) {
            Ten Fp = F, Fm = F;
            Fp[k][L] += h;
            Fm[k][L] -= h;
            const Ten dP =
                (point.step(Fp, dt, vol).first_piola - point.step(Fm, dt, vol).first_piola) /
                (2 * h);
            for (unsigned int i = 0; i < 3; ++i)
              for (unsigned int J = 0; J < 3; ++J)
                max_err = std::max(max_err, std::abs(dP[i][J] - exact.tangent[i][J][k][L]));
          }
        const double rel = max_err / exact.tangent.norm();
        std::printf("%4s %10.0e %6d %12.3e %12.4e %12.3e\n", base->name().c_str(), ratio, vol,
                    Q.norm() / point.isochoric.norm(), exact.tangent.norm(), rel);
        EXPECT_GT(Q.norm(), 0.1 * point.isochoric.norm()); // the history matters
        EXPECT_LT(rel, 1e-6);
      }
    }
  }
}

// Cauchy stress of the law at F.
Sym cauchy(const StressTangent& st, const Ten& F) {
  return dealii::symmetrize(st.first_piola * dealii::transpose(F)) / dealii::determinant(F);
}

TEST(ViscoHyperelasticLaw, SmallStrainEqualsLinearProny) {
  const double mu = 1e6, kappa = 8e6;
  const std::vector<ViscousBranch> branches{{2.0, 1e-2}, {0.5, 0.1}};
  const ViscoHyperelasticLaw law(std::make_shared<NeoHookeanLaw>(mu, kappa), branches);
  std::vector<PronyBranch> prony;
  for (const ViscousBranch& b : branches)
    prony.push_back({b.beta * mu, 0.0, b.relaxation_time});
  const ViscoelasticMaterial linear(mu, kappa, prony);
  std::printf("\n%10s %10s %14s\n", "dt (s)", "strain", "max rel. diff");
  for (const double dt : {1e-4, 1e-2, 1.0}) {
    double err[2] = {0, 0};
    const double amplitudes[2] = {1e-4, 1e-5};
    for (int a = 0; a < 2; ++a) {
      Point point(law);
      std::vector<Sym> h(branches.size());
      Sym eps_old;
      const Ten F = general_F(amplitudes[a]);
      const Sym eps = dealii::symmetrize(F - dealii::unit_symmetric_tensor<3>());
      for (int n = 0; n < 40; ++n) { // strain applied in the first step, then held
        const StressTangent st = point.step(F, dt);
        point.commit(dt);
        Sym sigma = linear.long_term_stiffness() * eps;
        for (unsigned int i = 0; i < branches.size(); ++i) {
          double decay = 0, gamma = 0;
          ViscoelasticMaterial::step_factors(dt, prony[i].relaxation_time, decay, gamma);
          h[i] = decay * h[i] + gamma * (linear.branch_stiffness(i) * (eps - eps_old));
          sigma += h[i];
        }
        eps_old = eps;
        err[a] = std::max(err[a], (cauchy(st, F) - sigma).norm() / sigma.norm());
      }
      std::printf("%10.0e %10.0e %14.3e\n", dt, amplitudes[a], err[a]);
    }
    EXPECT_LT(err[1], 1e-4);
    // O(strain): ten times smaller strain, about ten times smaller difference.
    EXPECT_GT(err[0] / err[1], 7.0);
    EXPECT_LT(err[0] / err[1], 13.0);
  }
}

// Isochoric uniaxial F = diag(l, l^-1/2, l^-1/2) (J = 1: S_vol = 0). Neo-Hookean closed forms:
// S_iso_11 = mu (2/3)(1 - l^-3), S_iso_22 = mu (1 - l^3)/3.
Ten uniaxial(double l) {
  Ten F;
  F[0][0] = l;
  F[1][1] = F[2][2] = 1 / std::sqrt(l);
  return F;
}
double s11(double mu, double l) {
  return mu * 2.0 / 3.0 * (1 - 1 / (l * l * l));
}
double s22(double mu, double l) {
  return mu * (1 - l * l * l) / 3.0;
}

TEST(ViscoHyperelasticLaw, StepRelaxationUnderFiniteStretch) {
  const double mu = 1e6, lambda = 1.5;
  const std::vector<ViscousBranch> branches{{1.5, 0.1}, {0.5, 1.0}};
  const ViscoHyperelasticLaw law(std::make_shared<NeoHookeanLaw>(mu, 1e8), branches);
  // The stretch is applied over a first step dt0 << tau (the instantaneous response), then held.
  const double dt0 = 1e-10;
  const Ten F = uniaxial(lambda);
  std::printf("\n%10s %14s\n", "dt (s)", "max rel. err");
  for (const double dt : {1e-3, 0.1, 100.0}) {
    Point point(law);
    point.step(F, dt0);
    point.commit(dt0);
    double t = dt0, err = 0;
    for (int n = 0; n < 30; ++n) {
      const StressTangent st = point.step(F, dt);
      point.commit(dt);
      t += dt;
      double factor = 1;
      for (const ViscousBranch& b : branches)
        factor += b.beta * std::exp(-t / b.relaxation_time);
      err = std::max({err, std::abs(st.second_piola[0][0] / (s11(mu, lambda) * factor) - 1),
                      std::abs(st.second_piola[1][1] / (s22(mu, lambda) * factor) - 1)});
    }
    std::printf("%10.0e %14.3e\n", dt, err);
    EXPECT_LT(err, 1e-8);
  }
}

// Q_11, Q_22 of one branch (beta, tau) at time t under the ramp l(s) = 1 + r s (s < t_r), held
// afterwards: beta int_0^min(t, t_r) e^{-(t-s)/tau} dS_iso/dl r ds by composite Gauss-Legendre.
void ramp_overstress(double mu, double beta, double tau, double r, double t_r, double t,
                     double& q11, double& q22) {
  static const double x[5] = {-0.9061798459386640, -0.5384693101056831, 0.0, 0.5384693101056831,
                              0.9061798459386640};
  static const double w[5] = {0.2369268850561891, 0.4786286704993665, 0.5688888888888889,
                              0.4786286704993665, 0.2369268850561891};
  const double end = std::min(t, t_r);
  const int panels = 2000;
  const double h = end / panels;
  q11 = q22 = 0;
  for (int p = 0; p < panels; ++p)
    for (int g = 0; g < 5; ++g) {
      const double s = (p + 0.5 + 0.5 * x[g]) * h, l = 1 + r * s;
      const double kernel = beta * std::exp(-(t - s) / tau) * r * 0.5 * h * w[g];
      q11 += kernel * 2 * mu / (l * l * l * l);
      q22 += kernel * (-mu * l * l);
    }
}

TEST(ViscoHyperelasticLaw, RampRelaxationUnderFiniteStretch) {
  const double mu = 1e6, beta = 2.0, tau = 0.1;
  const ViscoHyperelasticLaw law(std::make_shared<NeoHookeanLaw>(mu, 1e8),
                                 std::vector<ViscousBranch>{{beta, tau}});
  const double t_r = 10 * tau, t_end = 30 * tau, r = 0.5 / t_r; // lambda 1 -> 1.5 over t_r
  std::printf("\n%10s %14s %14s\n", "dt/tau", "max rel. err", "|Q|max/S_iso");
  std::vector<double> errors;
  for (const double ratio : {1e-2, 5e-3, 1.0, 10.0}) {
    const double dt = ratio * tau;
    const int n_steps = static_cast<int>(std::lround(t_end / dt));
    Point point(law);
    double err = 0, q_max = 0;
    for (int n = 1; n <= n_steps; ++n) {
      const double t = n * dt, l = 1 + r * std::min(t, t_r);
      const StressTangent st = point.step(uniaxial(l), dt);
      point.commit(dt);
      double q11 = 0, q22 = 0;
      ramp_overstress(mu, beta, tau, r, t_r, t, q11, q22);
      const double scale = s11(mu, 1.5) - s22(mu, 1.5);
      err = std::max({err, std::abs(st.second_piola[0][0] - s11(mu, l) - q11) / scale,
                      std::abs(st.second_piola[1][1] - s22(mu, l) - q22) / scale});
      q_max = std::max(q_max, std::abs(q11) / scale);
    }
    std::printf("%10.0e %14.3e %14.3e\n", ratio, err, q_max);
    errors.push_back(err);
  }
  EXPECT_LT(errors[0], 1e-4);
  // O(dt^2) for dt << tau: halving dt divides the error by 4.
  EXPECT_NEAR(errors[0] / errors[1], 4.0, 0.2);
  // dt ~ tau and dt >> tau: stable, bounded by the overstress scale.
  EXPECT_LT(errors[2], 0.05);
  EXPECT_LT(errors[3], 0.2);
}

// Simple shear gamma(t) = gamma0 t / T for t <= T, then held. A linear Maxwell branch (G, tau)
// carries q = G tau r (1 - e^{-t/tau}), r = gamma0 / T, and dissipates q^2 / (G tau):
//   D(T) = G tau r^2 [T - 2 tau (1 - e^{-T/tau}) + tau/2 (1 - e^{-2T/tau})],
//   D(inf) = G gamma0^2 (tau/T) [1 - (tau/T)(1 - e^{-T/tau})] (all the work it received).
TEST(ViscoHyperelasticLaw, DissipationOfAShearRampAgainstMaxwellClosedForms) {
  const double mu = 1e6, kappa = 8e6, T = 0.02;
  const std::vector<ViscousBranch> branches{{2.0, 1e-2}, {0.5, 0.1}};
  const ViscoHyperelasticLaw law(std::make_shared<NeoHookeanLaw>(mu, kappa), branches);
  std::printf("\n%8s %10s %14s %14s\n", "steps", "gamma0", "D(T) rel.err", "D(inf) rel.err");
  for (const int n_ramp : {1, 4, 200}) {
    double err[2][2];
    const double amplitudes[2] = {1e-3, 1e-4};
    for (int a = 0; a < 2; ++a) {
      const double gamma0 = amplitudes[a], r = gamma0 / T;
      double exact_ramp = 0, exact_total = 0;
      for (const ViscousBranch& b : branches) {
        const double g = b.beta * mu, tau = b.relaxation_time;
        exact_ramp += g * tau * r * r *
                      (T + 2 * tau * std::expm1(-T / tau) - 0.5 * tau * std::expm1(-2 * T / tau));
        exact_total += g * gamma0 * gamma0 * (tau / T) * (1 + (tau / T) * std::expm1(-T / tau));
      }
      Point point(law);
      double dissipated = 0;
      const double dt = T / n_ramp;
      Ten F = dealii::unit_symmetric_tensor<3>();
      for (int n = 1; n <= n_ramp; ++n) {
        F[0][1] = gamma0 * n / n_ramp;
        point.step(F, dt);
        dissipated += point.commit(dt);
      }
      err[a][0] = std::abs(dissipated - exact_ramp) / exact_ramp;
      for (int n = 0; n < 400; ++n) { // held 4 s = 40 tau_2 in steps of 10 ms
        point.step(F, 1e-2);
        dissipated += point.commit(1e-2);
      }
      err[a][1] = std::abs(dissipated - exact_total) / exact_total;
      std::printf("%8d %10.0e %14.3e %14.3e\n", n_ramp, gamma0, err[a][0], err[a][1]);
    }
    for (int k = 0; k < 2; ++k) {
      // The time integration is exact; what is left is the finite-strain law's departure from
      // the linear one, O(gamma0^2) in simple shear (Neo-Hookean S_12 = mu gamma (1 +
      // gamma^2/3), normal overstresses O(gamma^2)): measured 1.3-1.8 gamma0^2.
      EXPECT_LT(err[1][k], 2.5 * amplitudes[1] * amplitudes[1]);
      EXPECT_GT(err[0][k] / err[1][k], 70.0);
      EXPECT_LT(err[0][k] / err[1][k], 130.0);
    }
  }
}

TEST(ViscoHyperelasticLaw, SceneSyntax) {
  const auto specs = parse_material_specs(
      "a: law=neo_hookean, E=3e6, nu=0.45, beta1=1.5, tau1=1e-3, G2=2e5, tau2=0.1; "
      "b: law=mooney_rivlin, C10=0.5e6, C01=0.1e6, kappa=1e8; "
      "c: law=mooney_rivlin, C10=0.5e6, C01=0.1e6, kappa=1e8, G1=6e5, tau1=0.5",
      "materials");
  PhysicalGroups groups;
  groups.file = "test.msh";
  groups.volumes = {{"a", 1}, {"b", 2}, {"c", 3}};
  groups.n_cells = {{1, 1}, {2, 1}, {3, 1}};
  const HyperelasticMaterialTable table(specs, groups);
  ASSERT_NE(table.viscous(1), nullptr);
  EXPECT_EQ(table.viscous(2), nullptr);
  ASSERT_NE(table.viscous(3), nullptr);
  const ViscoHyperelasticLaw& a = *table.viscous(1);
  const double mu_a = 3e6 / (2 * 1.45);
  ASSERT_EQ(a.n_branches(), 2u);
  EXPECT_DOUBLE_EQ(a.branches()[0].beta, 1.5);
  EXPECT_DOUBLE_EQ(a.branches()[0].relaxation_time, 1e-3);
  EXPECT_NEAR(a.branches()[1].beta, 2e5 / mu_a, 1e-14);
  EXPECT_NEAR(a.instantaneous_shear_modulus(), mu_a * (1 + 1.5 + 2e5 / mu_a), 1e-6);
  EXPECT_EQ(&a.base(), &table[1]);
  EXPECT_NEAR(table.viscous(3)->branches()[0].beta, 0.5, 1e-14); // G1 / (2 (C10 + C01))
  EXPECT_NEAR(table[1].small_strain_youngs_modulus(), 3e6, 1e-6);

  const auto bad =
      parse_material_specs("x: law=neo_hookean, E=3e6, nu=0.45, beta1=-1, tau1=1; "
                           "y: law=neo_hookean, E=3e6, nu=0.45, beta1=1; "
                           "z: law=neo_hookean, E=3e6, nu=0.45, beta2=1, tau2=1; "
                           "w: law=neo_hookean, E=3e6, nu=0.45, beta1=1, G1=1e5, tau1=1; "
                           "v: law=neo_hookean, E=3e6, nu=0.45, beta1=1, tau1=0; "
                           "u: law=neo_hookean, E=3e6, nu=0.45, G1=-2, tau1=1",
                           "materials");
  const std::map<std::string, std::string> expected{
      {"x", "beta1 = -1"},  {"y", "tau1"},     {"z", "branch 1 is missing"},
      {"w", "exactly one"}, {"v", "tau1 = 0"}, {"u", "G1 = -2"}};
  for (const auto& [name, spec] : bad) {
    try {
      make_hyperelastic_law(spec);
      ADD_FAILURE() << "no exception for " << name;
    } catch (const std::invalid_argument& e) {
      std::printf("bad input %s -> %s\n", name.c_str(), e.what());
      EXPECT_NE(std::string(e.what()).find("'" + name + "'"), std::string::npos);
      EXPECT_NE(std::string(e.what()).find(expected.at(name)), std::string::npos);
    }
  }
}

} // namespace
} // namespace plantar::fem
