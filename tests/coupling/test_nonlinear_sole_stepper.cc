// A hyperelastic sole in the multibody stepper (issue 7): a free rigid foot block (58 kg,
// 0.2172 x 0.138 x 0.1 m) dropped on a Neo-Hookean sole (0.02 m, Q1 6 x 4 x 2, nu = 0.3)
// fixed under it. The sole is coupling::NonlinearCondensedSole; after each step its forces
// update the Newton state and, on re-condensation, the stepper's patch compliance and offset
// (coupling::PadState::set_compliance). Compared with the linear sole of the same E, nu (the
// compliance at u = 0, never updated):
//  - PadState::set_compliance: an offset d_z = delta on every node lowers the resting
//    foot by delta (U = C F + d at the same F);
//  - linear limit: at small strain the runs agree (final sink within 1 %); the differences
//    (final sink, max sole compression, peak force) grow monotonically with the strain
//    (E = 8, 2, 0.5 MPa). Differences below the re-condensation tolerance are not resolved:
//    the affine model is kept while its prediction error stays below it;
//  - the coupled state at rest is the sole's Newton solution at the final forces (error below
//    the re-condensation tolerance); re-condensations and the tolerated error are reported.
#include "condensation_test_utilities.h"
#include "coupling/nonlinear_condensed_sole.h"
#include "coupling/pad_state.h"
#include "fem/hyperelastic_law.h"
#include "foot_block_model.h"
#include "multibody/stepper.h"
#include "multibody/urdf_loader.h"

#include <gtest/gtest.h>

#include <Eigen/Geometry>

#include <cmath>
#include <cstdio>
#include <memory>
#include <vector>

namespace plantar::coupling {
namespace {

constexpr double L = 0.2172, W = 0.138, T = 0.02, H = 0.1, mass = 58.0, g = 9.81;
constexpr double tolerance = 0.02; // re-condensation tolerance

multibody::Model foot_model() {
  return ::plantar::test::foot_block_model(mass, L, W, H);
}

std::unique_ptr<NonlinearCondensedSole> make_sole(double E) {
  dealii::Triangulation<3> tria;
  testing::make_sole_box(tria, fem::CellKind::hexahedron, 6, 4, 2, L, W, T);
  const fem::HyperelasticMaterialTable materials(
      std::make_shared<fem::NeoHookeanLaw>(fem::NeoHookeanLaw::from_youngs(E, 0.3)));
  NonlinearCouplingParameters parameters;
  parameters.sole.recondensation_tolerance = tolerance;
  parameters.check_tolerance = 0.01;
  return std::make_unique<NonlinearCondensedSole>(tria, materials, 1, parameters);
}

struct Outcome {
  double sink = 0;              // final (H/2 + T) - base z, m
  double max_compression = 0;   // max node U_n over the run, m
  double peak_force = 0;        // max total normal force, N
  double final_force = 0;       // N
  double peak_acceleration = 0; // max |a_z| of the block, m/s^2
  double fixed_point_error = 0; // ||U - u_Newton(F)|| / ||U|| at the end (nonlinear only)
  unsigned int recondensations = 0;
  double tolerated = 0;
  int checks = 0;
};

enum class SoleModel { linear, nonlinear };

Outcome simulate(const multibody::Model& model, NonlinearCondensedSole& sole, SoleModel kind,
                 double drop, double duration, double offset_z = 0) {
  const double dt = 1e-3;
  const int n = sole.n_contacts();
  Eigen::Matrix3Xd nodes = sole.contact_positions().transpose();
  nodes.row(2).array() -= H / 2; // sole top at the block's bottom face
  multibody::StepperParameters parameters;
  parameters.time_step = dt;
  parameters.max_contacts = n;
  multibody::Stepper stepper(model, parameters);
  coupling::PadState pad(sole.compliance());
  stepper.add_deformable_patch(1, nodes, 1.0, pad);
  if (offset_z != 0) {
    Eigen::VectorXd d = Eigen::VectorXd::Zero(3 * n);
    for (int k = 0; k < n; ++k)
      d[3 * k + 2] = offset_z;
    pad.set_compliance(sole.compliance(), d);
  }
  Eigen::VectorXd q(7), v = Eigen::VectorXd::Zero(6);
  q << 0, 0, H / 2 + T + drop, 0, 0, 0, 1;
  const Eigen::VectorXd zero = Eigen::VectorXd::Zero(6);
  Outcome out;
  Eigen::VectorXd forces(3 * n);
  double vz_prev = 0;
  const int steps = static_cast<int>(std::lround(duration / dt));
  for (int i = 0; i < steps; ++i) {
    stepper.step(q, v, zero, q, zero);
    const Eigen::Matrix3d r = Eigen::Quaterniond(q[6], q[3], q[4], q[5]).toRotationMatrix();
    const double vz = (r * v.head<3>()).z();
    out.peak_acceleration = std::max(out.peak_acceleration, std::abs(vz - vz_prev) / dt);
    vz_prev = vz;
    out.peak_force = std::max(out.peak_force, stepper.total_contact_force().z());
    const Eigen::VectorXd& u = pad.displacement();
    for (int k = 0; k < n; ++k) {
      out.max_compression = std::max(out.max_compression, u[3 * k]);
      // Contact frame (n, t1, t2) = world (z, x, y) -> sole (= body) frame.
      const Eigen::Vector3d& p = stepper.node_impulse(0, k);
      forces.segment<3>(3 * k) = r.transpose() * Eigen::Vector3d(p[1], p[2], p[0]) / dt;
    }
    if (kind == SoleModel::nonlinear) {
      if (sole.update(forces).recondensed) {
        Eigen::MatrixXd c = sole.compliance();
        pad.set_compliance(c, sole.offset());
      }
    }
  }
  out.sink = H / 2 + T - q[2];
  out.final_force = stepper.total_contact_force().z();
  if (kind == SoleModel::nonlinear) {
    // Stepper displacements (contact frame, level block: (n, t1, t2) = sole (z, x, y)).
    const Eigen::VectorXd& u = pad.displacement();
    Eigen::VectorXd u_sole(3 * n);
    for (int k = 0; k < n; ++k)
      u_sole.segment<3>(3 * k) << u[3 * k + 1], u[3 * k + 2], u[3 * k];
    sole.deformation_field(forces);
    out.fixed_point_error = (u_sole - sole.contact_displacements()).norm() / u_sole.norm();
    out.recondensations = sole.n_recondensations();
    out.tolerated = sole.max_tolerated_error();
    out.checks = sole.n_checks();
  }
  return out;
}

TEST(NonlinearSoleStepper, OffsetLowersTheRestingFoot) {
  const multibody::Model model = foot_model();
  auto sole = make_sole(4e6);
  const double delta = 1e-4;
  const Outcome base = simulate(model, *sole, SoleModel::linear, 0.0, 0.5);
  const Outcome shifted = simulate(model, *sole, SoleModel::linear, 0.0, 0.5, delta);
  const double shift = shifted.sink - base.sink;
  std::printf("\nOffset d_z = %.1e m on every node: sink %.6e -> %.6e m, shift %.6e m "
              "(rel. error %.2e, tol 1e-3); force %.2f N (weight %.2f N)\n",
              delta, base.sink, shifted.sink, shift, std::abs(shift / delta - 1),
              shifted.final_force, mass * g);
  EXPECT_NEAR(shift / delta, 1.0, 1e-3);
  EXPECT_NEAR(shifted.final_force / (mass * g), 1.0, 1e-4);
}

TEST(NonlinearSoleStepper, LinearLimitAndGrowingDifferences) {
  const multibody::Model model = foot_model();
  const std::vector<double> moduli = {8e6, 2e6, 0.5e6};
  const double drop = 0.002;
  std::printf("\nFoot block %.0f kg dropped from %.3f m on a %.3f m sole (Q1 6x4x2, nu = 0.3), "
              "0.5 s, dt 1 ms;\nnonlinear (Neo-Hookean, re-condensation tolerance %.2f) vs "
              "linear sole of the same E, nu:\n",
              mass, drop, T, tolerance);
  std::printf("%8s %12s %12s %9s %12s %12s %9s %10s %9s %9s %7s %7s %9s %9s\n", "E (MPa)",
              "sink NL (m)", "sink lin", "diff", "max u NL", "max u lin", "diff", "F peak NL",
              "F lin", "diff", "checks", "recond", "tolerated", "fixed pt");
  std::vector<double> sink_diff, compression_diff, force_diff;
  for (const double E : moduli) {
    auto nonlinear_sole = make_sole(E);
    auto linear_sole = make_sole(E);
    const Outcome nl = simulate(model, *nonlinear_sole, SoleModel::nonlinear, drop, 0.5);
    const Outcome lin = simulate(model, *linear_sole, SoleModel::linear, drop, 0.5);
    sink_diff.push_back(std::abs(nl.sink / lin.sink - 1));
    compression_diff.push_back(std::abs(nl.max_compression / lin.max_compression - 1));
    force_diff.push_back(std::abs(nl.peak_force / lin.peak_force - 1));
    std::printf("%8.2f %12.5e %12.5e %9.2e %12.5e %12.5e %9.2e %10.1f %9.1f %9.2e %7d %7u %9.2e "
                "%9.2e\n",
                E / 1e6, nl.sink, lin.sink, sink_diff.back(), nl.max_compression,
                lin.max_compression, compression_diff.back(), nl.peak_force, lin.peak_force,
                force_diff.back(), nl.checks, nl.recondensations, nl.tolerated,
                nl.fixed_point_error);
    EXPECT_LT(nl.fixed_point_error, tolerance);
    EXPECT_LT(nl.tolerated, tolerance);
  }
  // Linear limit: strain ~0.3 % at E = 8 MPa.
  EXPECT_LT(sink_diff.front(), 0.01);
  for (std::size_t i = 1; i < moduli.size(); ++i) {
    EXPECT_GT(sink_diff[i], sink_diff[i - 1]);
    EXPECT_GT(compression_diff[i], compression_diff[i - 1]);
    EXPECT_GT(force_diff[i], force_diff[i - 1]);
  }
}

} // namespace
} // namespace plantar::coupling
