// NonlinearCondensedSole (coupling/nonlinear_condensed_sole.h):
//  - linear limit: at u = 0 its C_T equals the linear CondensedSole's C of the same mesh
//    and small-strain E, nu (independent assembly and solver: CHOLMOD on the linear
//    stiffness; only the unit-load loop, fem/contact_condensation.h, is shared), d = 0;
//  - the affine model u_c ~ C_T f + d is exact at the condensation state and C_T matches
//    central finite differences of Newton solutions there;
//  - under a load ramp the re-condensed model predicts the Newton solution better than the
//    u = 0 (linear) compliance; at small loads nothing is re-condensed;
//  - checks are skipped while the forces do not move; bad input is reported.
#include "condensation_test_utilities.h"
#include "coupling/nonlinear_condensed_sole.h"
#include "fem/hyperelastic_law.h"

#include <gtest/gtest.h>

#include <cstdio>
#include <memory>
#include <string>

namespace plantar::coupling {
namespace {

constexpr double a = 0.12, b = 0.06, c = 0.02; // sole box (m)

struct SoleBox {
  dealii::Triangulation<3> tria;
  std::shared_ptr<fem::NeoHookeanLaw> law;
  SoleBox(double E, double nu) {
    testing::make_sole_box(tria, fem::CellKind::hexahedron, 6, 3, 2, a, b, c);
    law = std::make_shared<fem::NeoHookeanLaw>(fem::NeoHookeanLaw::from_youngs(E, nu));
  }
};

NonlinearCouplingParameters coupling_parameters(double recondensation, double check) {
  NonlinearCouplingParameters p;
  p.sole.attached_boundary = 0;
  p.sole.contact_boundary = 1;
  p.sole.recondensation_tolerance = recondensation;
  p.check_tolerance = check;
  return p;
}

// Equal vertical nodal forces totalling @p total (N, +z pushes the sole up).
Eigen::VectorXd vertical_forces(int n_contacts, double total) {
  Eigen::VectorXd f = Eigen::VectorXd::Zero(3 * n_contacts);
  for (int k = 0; k < n_contacts; ++k)
    f[3 * k + 2] = total / n_contacts;
  return f;
}

TEST(NonlinearCondensedSole, LinearLimitEqualsCondensedSole) {
  const double E = 4e6, nu = 0.3;
  SoleBox setup(E, nu);
  const fem::HyperelasticMaterialTable materials(setup.law);
  NonlinearCondensedSole nonlinear(setup.tria, materials, 1, coupling_parameters(0.05, 0.0));
  CondensationParameters linear_parameters;
  const CondensedSole linear(setup.tria, materials.linearized(), linear_parameters);
  ASSERT_EQ(nonlinear.n_contacts(), linear.n_contacts());
  const int n = nonlinear.n_contacts();
  // Node map by position (the two classes number their nodes independently).
  std::vector<int> map(n, -1);
  for (int k = 0; k < n; ++k)
    for (int j = 0; j < n; ++j)
      if ((nonlinear.contact_positions().row(k) - linear.contact_positions().row(j)).norm() < 1e-12)
        map[k] = j;
  double max_diff = 0;
  for (int k = 0; k < n; ++k) {
    ASSERT_GE(map[k], 0);
    for (int l = 0; l < n; ++l)
      max_diff = std::max(max_diff, (nonlinear.compliance().block<3, 3>(3 * k, 3 * l) -
                                     linear.compliance().block<3, 3>(3 * map[k], 3 * map[l]))
                                        .cwiseAbs()
                                        .maxCoeff());
  }
  const double rel = max_diff / linear.compliance().cwiseAbs().maxCoeff();
  std::printf("\nLinear limit, %d contact nodes: max |C_T(0) - C_linear| / max |C| = %.2e "
              "(tol 1e-8), |d| = %.1e\n",
              n, rel, nonlinear.offset().norm());
  EXPECT_LT(rel, 1e-8);
  EXPECT_EQ(nonlinear.offset().norm(), 0.0);
}

TEST(NonlinearCondensedSole, AffineModelAndRecondensation) {
  const double E = 2e6, nu = 0.3;
  SoleBox setup(E, nu);
  const fem::HyperelasticMaterialTable materials(setup.law);
  // Tolerance 1e-9: every check re-condenses.
  NonlinearCondensedSole sole(setup.tria, materials, 1, coupling_parameters(1e-9, 0.0));
  const int n = sole.n_contacts();
  const double total = 0.15 * E * a * b; // mean pressure 0.15 E: about 15 % compression
  const Eigen::VectorXd f1 = vertical_forces(n, total);
  const NonlinearUpdateReport r1 = sole.update(f1);
  EXPECT_TRUE(r1.checked);
  EXPECT_TRUE(r1.recondensed);
  const Eigen::VectorXd u1 = sole.contact_displacements();
  const double exact_at_state = (sole.compliance() * f1 + sole.offset() - u1).norm() / u1.norm();
  // C_T against central differences of Newton solutions around f1.
  const Eigen::MatrixXd c_t = sole.compliance();
  const Eigen::VectorXd d_t = sole.offset();
  const Eigen::VectorXd df = vertical_forces(n, 1e-3 * total) +
                             Eigen::VectorXd::Constant(3 * n, 1e-4 * total / n); // all components
  NonlinearCondensedSole probe(setup.tria, materials, 1, coupling_parameters(1e9, 0.0));
  probe.deformation_field(f1 + df);
  const Eigen::VectorXd u_plus = probe.contact_displacements();
  probe.deformation_field(f1 - df);
  const Eigen::VectorXd u_minus = probe.contact_displacements();
  const Eigen::VectorXd fd = (u_plus - u_minus) / 2;
  const double fd_error = (c_t * df - fd).norm() / fd.norm();
  // A further 10 % load: the tangent model against the linear (u = 0) compliance.
  const Eigen::VectorXd f2 = 1.1 * f1;
  probe.deformation_field(f2);
  const Eigen::VectorXd u2 = probe.contact_displacements();
  NonlinearCondensedSole at_zero(setup.tria, materials, 1, coupling_parameters(1e9, 0.0));
  const double tangent_error = (c_t * f2 + d_t - u2).norm() / u2.norm();
  const double linear_error = (at_zero.compliance() * f2 - u2).norm() / u2.norm();
  std::printf("\nSole %gx%gx%g m, E = %.0e, nu = %.2f, force %.0f N (max u_z %.3e m):\n"
              "  |C_T f1 + d - u(f1)| / |u| = %.2e (tol 1e-10)\n"
              "  C_T vs central differences of Newton: %.2e (tol 1e-4)\n"
              "  at 1.1 f1: tangent model error %.2e, linear (u = 0) model error %.2e\n",
              a, b, c, E, nu, total, u1.cwiseAbs().maxCoeff(), exact_at_state, fd_error,
              tangent_error, linear_error);
  EXPECT_LT(exact_at_state, 1e-10);
  EXPECT_LT(fd_error, 1e-4);
  EXPECT_LT(tangent_error, 0.1 * linear_error);
  EXPECT_EQ(sole.n_recondensations(), 1u);
}

TEST(NonlinearCondensedSole, SmallLoadsNeverRecondenseAndSkipChecks) {
  const double E = 4e6, nu = 0.3;
  SoleBox setup(E, nu);
  const fem::HyperelasticMaterialTable materials(setup.law);
  NonlinearCondensedSole sole(setup.tria, materials, 1, coupling_parameters(0.01, 0.02));
  const int n = sole.n_contacts();
  const double p_small = 1e-4 * E; // strain ~1e-4
  std::printf("\nRamp to mean pressure %.0f Pa in 20 steps, then 20 steps held:\n", p_small);
  for (int step = 1; step <= 40; ++step) {
    const double s = std::min(step, 20) / 20.0;
    sole.update(vertical_forces(n, s * p_small * a * b));
  }
  std::printf("  checks %d of 40 calls, re-condensations %u, max tolerated error %.2e "
              "(tolerance 0.01), Newton iterations %u\n",
              sole.n_checks(), sole.n_recondensations(), sole.max_tolerated_error(),
              sole.newton_iterations());
  EXPECT_EQ(sole.n_recondensations(), 0u);
  EXPECT_GT(sole.max_tolerated_error(), 0.0);
  EXPECT_LT(sole.max_tolerated_error(), 0.01);
  // Held forces: no check after the ramp; during the ramp steps change by >= 5 % (> 2 %).
  EXPECT_EQ(sole.n_checks(), 20);
  // The first-order error of the linear model: e ~ strain, so 1e-4 here (within 10x).
  EXPECT_LT(sole.max_tolerated_error(), 1e-3);
}

TEST(NonlinearCondensedSole, BadInput) {
  SoleBox setup(4e6, 0.3);
  const fem::HyperelasticMaterialTable materials(setup.law);
  auto bad = coupling_parameters(0.05, 2.0);
  try {
    NonlinearCondensedSole sole(setup.tria, materials, 1, bad);
    FAIL() << "no exception";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("check_tolerance = 2"), std::string::npos) << e.what();
  }
  NonlinearCondensedSole sole(setup.tria, materials, 1, coupling_parameters(0.05, 0.0));
  try {
    sole.update(Eigen::VectorXd::Zero(5));
    FAIL() << "no exception";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("expected 3 n_c"), std::string::npos) << e.what();
  }
}

} // namespace
} // namespace plantar::coupling
