// NonlinearCondensedSole with visco-hyperelastic regions (coupling/nonlinear_condensed_sole.h),
// on a Neo-Hookean sole box (Q1 6 x 3 x 2, top attached):
//  - the work accounting: over a non-proportional load cycle of an elastic sole, work() equals
//    the stored energy int W dV at every check (the quadrature, trapezoid plus end-slope term, is
//    exact for a quadratic map, the strain is small) and closes to ~0 when the load returns to 0;
//  - creep at constant force: the affine model C_T f + d the stepper sees follows a
//    fem::NonlinearSole integrated step by step (set_time_step(dt), an update every step)
//    to the order of the check tolerance, with checks fired on time only, fewer than the steps.
#include "condensation_test_utilities.h"
#include "coupling/nonlinear_condensed_sole.h"
#include "fem/hyperelastic_law.h"
#include "fem/visco_hyperelastic_fields.h"
#include "fem/visco_hyperelastic_law.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <memory>

namespace plantar::coupling {
namespace {

constexpr double a = 0.12, b = 0.06, c = 0.02; // sole box (m)

NonlinearCouplingParameters parameters(double time_step) {
  NonlinearCouplingParameters p;
  p.sole.attached_boundary = 0;
  p.sole.contact_boundary = 1;
  p.sole.recondensation_tolerance = 0.02;
  p.sole.time_step = time_step;
  p.check_tolerance = 0.02;
  return p;
}

/// A fixed non-uniform load shape (3 n, N per unit amplitude): upward with tangential parts.
Eigen::VectorXd load_shape(int n) {
  Eigen::VectorXd f(3 * n);
  for (int k = 0; k < n; ++k) {
    f[3 * k] = 0.3 * std::sin(1.7 * k);
    f[3 * k + 1] = 0.2 * std::cos(2.3 * k);
    f[3 * k + 2] = 1.0 + 0.5 * std::sin(0.9 * k);
  }
  return f * (300.0 / n);
}

TEST(ViscoHyperelasticCoupling, WorkEqualsStoredEnergyOverAnElasticCycle) {
  dealii::Triangulation<3> tria;
  testing::make_sole_box(tria, fem::CellKind::hexahedron, 6, 3, 2, a, b, c);
  const fem::HyperelasticMaterialTable materials(
      std::make_shared<fem::NeoHookeanLaw>(fem::NeoHookeanLaw::from_youngs(4e7, 0.3)));
  NonlinearCondensedSole sole(tria, materials, 1, parameters(0));
  const Eigen::VectorXd shape = load_shape(sole.n_contacts());
  const Eigen::VectorXd twist = load_shape(sole.n_contacts()).reverse(); // another shape
  double peak = 0;
  for (const double s : {0.2, 0.6, 1.0, 0.7, 0.3, 0.0}) {
    const Eigen::VectorXd f = s * shape + (1 - s) * (s > 0 ? 0.5 : 0.0) * twist;
    ASSERT_TRUE(sole.update(f).checked);
    const double stored = sole.stored_base_energy();
    peak = std::max(peak, stored);
    std::printf("load %.1f: work %.8e J, stored %.8e J\n", s, sole.work(), stored);
    // The trapezoid alone: 4e-5 of the peak (its O(df^3) error on these load jumps); with the
    // end-slope term 1.5e-7.
    EXPECT_NEAR(sole.work(), stored, 1e-6 * peak);
  }
}

TEST(ViscoHyperelasticCoupling, CreepAtConstantForceFollowsTheSole) {
  dealii::Triangulation<3> tria;
  testing::make_sole_box(tria, fem::CellKind::hexahedron, 6, 3, 2, a, b, c);
  const auto base = std::make_shared<fem::NeoHookeanLaw>(fem::NeoHookeanLaw::from_youngs(4e6, 0.3));
  const fem::HyperelasticMaterialTable materials(std::make_shared<fem::ViscoHyperelasticLaw>(
      base, std::vector<fem::ViscousBranch>{{1.0, 0.05}}));
  const double dt = 1e-3;
  NonlinearCondensedSole sole(tria, materials, 1, parameters(dt));
  fem::Discretization discretization(fem::CellKind::hexahedron, 1);
  fem::NonlinearSoleParameters reference_parameters = parameters(dt).sole;
  fem::NonlinearSole reference(tria, discretization, materials, reference_parameters);
  const Eigen::VectorXd f = load_shape(sole.n_contacts());
  dealii::Vector<double> load(f.size());
  for (int i = 0; i < f.size(); ++i)
    load(i) = f[i];
  double worst = 0;
  const int steps = 300; // 6 tau
  for (int step = 0; step < steps; ++step) {
    sole.update(f);
    reference.update(load);
    // What the stepper sees for the next step against the sole's state after it.
    const Eigen::VectorXd model = sole.compliance() * f + sole.offset();
    double difference = 0, norm = 0;
    for (int i = 0; i < f.size(); ++i) {
      difference += std::pow(model[i] - reference.contact_displacements()(i), 2);
      norm += std::pow(reference.contact_displacements()(i), 2);
    }
    worst = std::max(worst, std::sqrt(difference / norm));
  }
  std::printf("%d steps: %d checks (%d on time), %u re-condensations; worst |C f + d - u| / |u| "
              "= %.3e\n",
              steps, sole.n_checks(), sole.n_time_checks(), sole.n_recondensations(), worst);
  EXPECT_GT(sole.n_time_checks(), 0);
  EXPECT_EQ(sole.n_checks(), 1 + sole.n_time_checks()); // the force moved once
  EXPECT_LT(sole.n_checks(), steps / 2);
  // The time test allows a creep error of the order of the check tolerance (0.02).
  EXPECT_LT(worst, 1.5 * 0.02);

  // The dashpots' dissipation over the creep, integrated at the checks against every step, and
  // its cell field (cell means over the reference volume) against its total.
  const double at_checks = fem::dissipated_energy(sole.sole().elasticity());
  const double every_step = fem::dissipated_energy(reference.elasticity());
  const fem::ViscoelasticCellFields fields =
      fem::visco_hyperelastic_cell_fields(sole.sole().elasticity());
  double integral = 0;
  for (const auto& cell : tria.active_cell_iterators())
    integral += fields.dissipated_energy_density[cell->active_cell_index()] * cell->measure();
  std::printf("dissipated: %.6e J at the checks, %.6e J at every step; cell field %.6e J\n",
              at_checks, every_step, integral);
  ASSERT_EQ(fields.overstress.size(), 1u);
  EXPECT_GT(every_step, 0.0);
  EXPECT_NEAR(integral, at_checks, 1e-12 * at_checks);
  // Integrated between checks the stress path is taken linear in time over each interval:
  // measured 4.1e-3 of the every-step figure (27 checks against 300 steps).
  EXPECT_NEAR(at_checks, every_step, 1e-2 * every_step);
}

} // namespace
} // namespace plantar::coupling
