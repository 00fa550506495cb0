// Relaxation, creep and DMA of a viscoelastic bar through the condensed sole, against the Prony
// closed forms. The bar is nu = 0 in every branch (viscoelastic_test_utilities.h), so its FEM
// answer is the uniaxial law exactly and every difference below is the time integration's.
//
// Expected errors of the exponential recursive update (exact for a strain linear in time over
// each step):
//  - relaxation, strain ramped over the first step then held: exact (round-off) for any dt/tau;
//    against the ideal step eps0 H(t): the ramp's lag, |(tau/dt)(e^{dt/tau} - 1) - 1| E_i eps0
//    e^{-t/tau_i} per branch, first order (dt / 2 tau) for dt << tau.
//  - creep, force ramped over the first step then held: second order, O((dt/tau_min)^2), for
//    dt << tau; bounded (a few % of J_inf) for dt ~ tau; for dt >> tau the first step's
//    strain is off by at most sum_i E_i tau_i / (dt E_inf) of J_inf (the branches still carry
//    gamma_i E_i), then the long-term strain.
//  - DMA: second order in w dt for E', E'', tan delta, the energy per cycle (stress-strain
//    loop) and the dissipation accounted by the sole (closed form per step at the quadrature
//    points).
#include "viscoelastic_test_utilities.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

namespace plantar::fem {
namespace {

using testing::Bar;
using testing::CreepCompliance;
using testing::UniaxialProny;

UniaxialProny standard_linear_solid() {
  return {1e6, {{3e6, 1.0}}};
}
UniaxialProny three_branch() {
  return {1e6, {{2e6, 0.01}, {1.5e6, 0.1}, {1e6, 1.0}}};
}

// Axial stress of a ramp-then-hold strain history (ramp over [0, dt]) at t >= dt:
// E_inf eps0 + sum_i E_i eps0 (tau_i/dt) (e^{-(t-dt)/tau_i} - e^{-t/tau_i}) (the convolution).
double ramp_relaxation(const UniaxialProny& prony, double eps0, double t, double dt) {
  double stress = prony.long_term * eps0;
  for (const auto& [modulus, tau] : prony.terms)
    stress += modulus * eps0 * (tau / dt) * (std::exp(-(t - dt) / tau) - std::exp(-t / tau));
  return stress;
}

struct RelaxationErrors {
  double ramp = 0, step = 0, step_bound = 0; // max over t of |error| / E_0 eps0
};

RelaxationErrors relaxation(const UniaxialProny& prony, double dt, double t_end) {
  Bar bar(prony, dt);
  const double eps0 = 0.01;
  RelaxationErrors e;
  const int n = static_cast<int>(std::ceil(t_end / dt));
  for (int k = 1; k <= n; ++k) {
    const double t = k * dt;
    const double stress = bar.step_strain(eps0);
    const double scale = prony.instantaneous() * eps0;
    e.ramp = std::max(e.ramp, std::abs(stress - ramp_relaxation(prony, eps0, t, dt)) / scale);
    e.step = std::max(e.step, std::abs(stress - prony.relaxation(t) * eps0) / scale);
    double bound = 0; // sum_i E_i |(tau/dt)(e^{dt/tau} - 1) - 1| e^{-t/tau}, independent
    for (const auto& [modulus, tau] : prony.terms)
      bound += modulus * std::abs(std::expm1(dt / tau) * tau / dt - 1.0) * std::exp(-t / tau);
    e.step_bound = std::max(e.step_bound, bound * eps0 / scale);
  }
  return e;
}

TEST(ViscoelasticBar, RelaxationIsExactForARampedStrainAtAnyStep) {
  for (const UniaxialProny& prony : {standard_linear_solid(), three_branch()})
    for (const double ratio : {1e-2, 1.0, 1e2}) { // dt / tau_min
      const double dt = ratio * prony.tau_min();
      const RelaxationErrors e = relaxation(prony, dt, std::max(3.0 * prony.tau_max(), 5 * dt));
      SCOPED_TRACE(::testing::Message() << prony.terms.size() << " branches, dt/tau " << ratio);
      std::printf("relaxation, %zu branches, dt/tau_min %g: vs ramp %.1e, vs step %.1e "
                  "(closed-form lag %.1e)\n",
                  prony.terms.size(), ratio, e.ramp, e.step, e.step_bound);
      EXPECT_LT(e.ramp, 1e-11);
      // Against the ideal step: the ramp's lag, within 10 % of its closed-form size.
      EXPECT_LE(e.step, 1.1 * e.step_bound + 1e-11);
      if (ratio < 1) {
        EXPECT_LT(e.step, ratio); // first order: ~ (dt / 2 tau) E_i / E_0
      }
    }
}

TEST(ViscoelasticBar, RelaxationAgainstTheStepIsFirstOrder) {
  const UniaxialProny prony = standard_linear_solid();
  const double coarse = relaxation(prony, 2e-3, 1.0).step;
  const double fine = relaxation(prony, 1e-3, 1.0).step;
  EXPECT_NEAR(coarse / fine, 2.0, 0.05);
}

struct CreepErrors {
  double ramp = 0, step = 0, first = 0, last = 0; // |error| / J_inf
};

CreepErrors creep(const UniaxialProny& prony, double dt, double t_end) {
  Bar bar(prony, dt);
  const CreepCompliance compliance(prony);
  const double stress = 1e4; // Pa
  const double j_inf = 1.0 / prony.long_term;
  CreepErrors e;
  const int n = static_cast<int>(std::ceil(t_end / dt));
  for (int k = 1; k <= n; ++k) {
    const double t = k * dt;
    const double strain = bar.step_force(stress * bar.area()) / stress; // J, 1/Pa
    const double ramp_error = std::abs(strain - compliance.ramp(t, dt)) / j_inf;
    e.ramp = std::max(e.ramp, ramp_error);
    e.step = std::max(e.step, std::abs(strain - compliance(t)) / j_inf);
    if (k == 1)
      e.first = ramp_error;
    e.last = ramp_error;
  }
  return e;
}

TEST(ViscoelasticBar, CreepClosedFormAtTimeZero) {
  // The independent closed form itself: J(0) = 1/E_0, J(inf) = 1/E_inf.
  for (const UniaxialProny& prony : {standard_linear_solid(), three_branch()}) {
    const CreepCompliance compliance(prony);
    EXPECT_NEAR(compliance(0.0) * prony.instantaneous(), 1.0, 1e-12);
    EXPECT_NEAR(compliance(1e3 * prony.tau_max()) * prony.long_term, 1.0, 1e-12);
  }
}

TEST(ViscoelasticBar, CreepSmallStepsAreSecondOrder) {
  for (const UniaxialProny& prony : {standard_linear_solid(), three_branch()}) {
    const double dt = 1e-2 * prony.tau_min();
    const double t_end = 2.0 * prony.tau_max();
    const CreepErrors coarse = creep(prony, 2 * dt, t_end), fine = creep(prony, dt, t_end);
    SCOPED_TRACE(::testing::Message() << prony.terms.size() << " branches");
    const double ratio = dt / prony.tau_min();
    std::printf("creep, %zu branches, dt/tau_min %g and %g: vs ramp %.2e %.2e, vs step %.2e "
                "%.2e\n",
                prony.terms.size(), ratio, 2 * ratio, fine.ramp, coarse.ramp, fine.step,
                coarse.step);
    EXPECT_LT(fine.ramp, 0.05 * ratio * ratio);
    EXPECT_NEAR(coarse.ramp / fine.ramp, 4.0, 0.4);
    // Against the step load: first order (the load's ramp over the first step).
    EXPECT_LT(fine.step, 2.0 * ratio);
    EXPECT_NEAR(coarse.step / fine.step, 2.0, 0.2);
  }
}

TEST(ViscoelasticBar, CreepStepsNearTauAreBoundedAndStepsBeyondTauReachTheLongTerm) {
  for (const UniaxialProny& prony : {standard_linear_solid(), three_branch()}) {
    SCOPED_TRACE(::testing::Message() << prony.terms.size() << " branches");
    const CreepErrors near = creep(prony, prony.tau_max(), 20.0 * prony.tau_max());
    EXPECT_LT(near.ramp, 0.05);
    EXPECT_LT(near.last, 0.1 * near.ramp); // the error decays with the creep
    const double dt = 100.0 * prony.tau_max();
    const CreepErrors beyond = creep(prony, dt, 10.0 * dt);
    double bound = 0; // sum_i E_i tau_i / (dt E_inf)
    for (const auto& [modulus, tau] : prony.terms)
      bound += modulus * tau / (dt * prony.long_term);
    std::printf("creep, %zu branches, dt = tau_max: vs ramp %.2e (last %.1e); dt = 100 "
                "tau_max: first step %.2e (bound %.2e), last %.1e\n",
                prony.terms.size(), near.ramp, near.last, beyond.first, bound, beyond.last);
    EXPECT_LT(beyond.first, bound);
    EXPECT_LT(beyond.last, 1e-12);
  }
}

TEST(ViscoelasticBar, HardCasesCreepStaysBetweenTheInstantaneousAndLongTermCompliances) {
  // tau from 10 us to 10 s in one series, dt from 0.1 to 10 ms (dt/tau from 1e-5 to 1e3):
  // under a held stress the strain rises monotonically from ~1/E_0 towards 1/E_inf and never
  // leaves [1/E_0, 1/E_inf] (unconditional stability of the recursive update).
  const UniaxialProny prony{1e6,
                            {{2e6, 1e-5}, {1e6, 1e-3}, {1e6, 1e-1}, {0.5e6, 1.0}, {0.5e6, 10.0}}};
  for (const double dt : {1e-4, 1e-3, 1e-2}) {
    Bar bar(prony, dt, 1);
    const double stress = 1e4, lower = 1 / prony.instantaneous(), upper = 1 / prony.long_term;
    double previous = 0;
    for (int k = 0; k < 300; ++k) {
      const double compliance = bar.step_force(stress * bar.area()) / stress;
      SCOPED_TRACE(::testing::Message() << "dt " << dt << ", step " << k);
      EXPECT_GE(compliance, lower * (1 - 1e-12));
      EXPECT_LE(compliance, upper * (1 + 1e-12));
      EXPECT_GE(compliance, previous * (1 - 1e-12));
      previous = compliance;
    }
  }
}

// DMA: eps(t) = eps0 sin(w t) at 0.1 Hz .. 1 kHz, N steps per period, run until the transient
// (e^{-t/tau_max}) is below 1e-6, then the last period's Fourier coefficients:
//   E' = (2 / (N eps0)) sum sigma_k sin(w t_k),  E'' = (2 / (N eps0)) sum sigma_k cos(w t_k),
// and the energy per cycle W = V sum (sigma_k + sigma_{k-1}) / 2 (eps_k - eps_{k-1}), against
//   E'(w) = E_inf + sum E_i w^2 tau_i^2 / (1 + w^2 tau_i^2),
//   E''(w) = sum E_i w tau_i / (1 + w^2 tau_i^2),  W = pi E'' eps0^2 V.
TEST(ViscoelasticBar, DynamicMechanicalAnalysis) {
  const UniaxialProny prony{1e6, {{2e6, 1e-3}, {1.5e6, 1e-2}, {1e6, 1e-1}}};
  const int per_period = 128;
  const double eps0 = 1e-3;
  for (const double frequency : {0.1, 1.0, 10.0, 100.0, 1000.0}) {
    const double w = 2 * M_PI * frequency, period = 1.0 / frequency, dt = period / per_period;
    Bar bar(prony, dt, 1);
    const double volume = Bar::length * Bar::side * Bar::side;
    const int periods =
        std::max(2, static_cast<int>(std::ceil(14.0 * prony.tau_max() / period)) + 1);
    const int n = periods * per_period;
    double sine = 0, cosine = 0, work = 0, previous_stress = 0, previous_strain = 0;
    double dissipated_before = 0; // the sole's dissipation account at the last period's start
    for (int k = 1; k <= n; ++k) {
      if (k == n - per_period + 1)
        dissipated_before = bar.sole->dissipated_energy();
      const double t = k * dt, strain = eps0 * std::sin(w * t);
      const double stress = bar.step_strain(strain);
      if (k > n - per_period) {
        sine += stress * std::sin(w * t);
        cosine += stress * std::cos(w * t);
        work += volume * 0.5 * (stress + previous_stress) * (strain - previous_strain);
      }
      previous_stress = stress;
      previous_strain = strain;
    }
    const double storage = 2 * sine / (per_period * eps0), loss = 2 * cosine / (per_period * eps0);
    double storage_exact = prony.long_term, loss_exact = 0;
    for (const auto& [modulus, tau] : prony.terms) {
      const double wt = w * tau;
      storage_exact += modulus * wt * wt / (1 + wt * wt);
      loss_exact += modulus * wt / (1 + wt * wt);
    }
    const double order = (w * dt) * (w * dt); // second order
    SCOPED_TRACE(::testing::Message() << frequency << " Hz");
    EXPECT_LT(std::abs(storage - storage_exact) / storage_exact, 0.3 * order);
    EXPECT_LT(std::abs(loss - loss_exact) / loss_exact, 0.3 * order);
    const double tan_delta = loss / storage, tan_delta_exact = loss_exact / storage_exact;
    EXPECT_LT(std::abs(tan_delta - tan_delta_exact) / tan_delta_exact, 0.5 * order);
    const double energy_exact = M_PI * loss_exact * eps0 * eps0 * volume;
    EXPECT_LT(std::abs(work - energy_exact) / energy_exact, 0.3 * order);
    // The dashpots' dissipation, integrated at the quadrature points in closed form over each
    // step (fem/viscoelastic_condensation.h): over a period, pi E'' eps0^2 V too.
    const double dissipated = bar.sole->dissipated_energy() - dissipated_before;
    EXPECT_LT(std::abs(dissipated - energy_exact) / energy_exact, 0.3 * order);
    std::printf("DMA %7.1f Hz: dissipated by the branches over the period %.6e J, rel. error "
                "%.1e\n",
                frequency, dissipated, std::abs(dissipated - energy_exact) / energy_exact);
    std::printf("DMA %7.1f Hz: E' %.6e (exact %.6e) E'' %.6e (exact %.6e) tan d %.4f W %.4e J "
                "(exact %.4e) rel errors %.1e %.1e %.1e, (w dt)^2 %.1e\n",
                frequency, storage, storage_exact, loss, loss_exact, tan_delta, work, energy_exact,
                std::abs(storage - storage_exact) / storage_exact,
                std::abs(loss - loss_exact) / loss_exact,
                std::abs(work - energy_exact) / energy_exact, order);
  }
}

} // namespace
} // namespace plantar::fem
