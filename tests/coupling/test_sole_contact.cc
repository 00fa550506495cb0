// A condensed FEM sole (coupling/condensed_sole) inside the frictional
// contact solver (coupling/contact), with a rigid block on top
// (tests/contact/rigid_body_harness):
// - pressed by its weight W: the total normal force is W, every node stays on
//   the ground, and the sole displacements of the contact loop equal a direct
//   FEM solve (UMFPACK, fem/) with the contact forces found (1e-8 relative);
// - compression with a frictionless versus a sticking ground: apparent
//   modulus E < E_a(frictionless) < E_a(sticking) < M (validation.md,
//   bonded block, nu = 0.3), and the friction state (tangential impulses zero
//   or strictly inside the cone) is the one asked for;
// - a tangential load of 0.1 W: with friction the block holds and the sole
//   shears with the bonded-layer stiffness G A / t; without friction the
//   block slides with a = F / m.
#include "condensation_test_utilities.h"
#include "tests/contact/rigid_body_harness.h"
#include "fem/linear_elasticity.h"

#include <gtest/gtest.h>

#include <cstdio>

namespace plantar::coupling {
namespace {

constexpr double L = 0.2172, W = 0.138, T = 0.02, E = 4e6, nu = 0.3, mass = 60.0, g = 9.81;
constexpr double block_height = 0.1, dt = 1e-3;

struct Fixture {
  dealii::Triangulation<3> tria;
  fem::MaterialTable materials{fem::LinearElasticMaterial(E, nu)};
  std::unique_ptr<CondensedSole> sole;
  Fixture() {
    testing::make_sole_box(tria, fem::CellKind::hexahedron, 11, 7, 2, L, W, T);
    CondensationParameters parameters;
    parameters.attached_boundary = 0;
    parameters.contact_boundary = 1;
    sole = std::make_unique<CondensedSole>(tria, materials, parameters);
  }
};

// The block with the sole's bottom nodes as its contact points; the patch
// compliance in the ground frame (n = z, t1 = x, t2 = y).
contact::test::RigidWorld make_world(const CondensedSole& sole, double friction, double tangential_force) {
  contact::test::RigidWorld world;
  contact::test::RigidBody block;
  block.mass = mass;
  block.principal_inertia = contact::test::box_inertia(mass, Eigen::Vector3d(L, W, block_height));
  block.position = Eigen::Vector3d(0, 0, block_height / 2 + T);
  block.force = Eigen::Vector3d(tangential_force, 0, 0);
  world.bodies.push_back(block);
  const int n = sole.n_contacts();
  Eigen::MatrixXd permutation = Eigen::MatrixXd::Zero(3 * n, 3 * n);
  for (int k = 0; k < n; ++k) {
    const Eigen::Vector3d node = sole.contact_positions().row(k).transpose();
    contact::test::PointContact contact;
    contact.point = Eigen::Vector3d(node.x(), node.y(), -block_height / 2 + node.z());
    contact.friction = friction;
    world.contacts.push_back(contact);
    permutation(3 * k + 0, 3 * k + 2) = 1; // n  <- z
    permutation(3 * k + 1, 3 * k + 0) = 1; // t1 <- x
    permutation(3 * k + 2, 3 * k + 1) = 1; // t2 <- y
  }
  world.set_patch(permutation * sole.compliance() * permutation.transpose());
  world.settings.tolerance = 1e-10;
  world.settings.max_iterations = 2000;
  // ADMM stalls on the frictionless (mu = 0) dense patch; Gauss-Seidel holds.
  if (friction == 0.0)
    world.settings.solver = contact::ContactSolverType::gauss_seidel;
  world.finalize();
  return world;
}

// Runs to rest (or for the given time); returns the total contact impulse
// per step in the ground frame (n, t1, t2) at the end.
Eigen::Vector3d run(contact::test::RigidWorld& world, double duration) {
  Eigen::Vector3d total = Eigen::Vector3d::Zero();
  const int steps = static_cast<int>(duration / dt);
  for (int i = 0; i < steps; ++i) {
    const auto result = world.step(dt);
    EXPECT_EQ(result.status, contact::SolverStatus::converged) << "step " << i;
  }
  for (std::size_t c = 0; c < world.contacts.size(); ++c)
    total += world.impulse(static_cast<int>(c));
  return total;
}

// Mean displacement of the bottom nodes, sole frame (x, y, z), from the
// patch displacement (n, t1, t2).
Eigen::Vector3d mean_displacement(const contact::test::RigidWorld& world, int n) {
  Eigen::Vector3d mean = Eigen::Vector3d::Zero();
  for (int k = 0; k < n; ++k)
    mean +=
        Eigen::Vector3d(world.patch_displacement()[3 * k + 1],
                        world.patch_displacement()[3 * k + 2], world.patch_displacement()[3 * k]) /
        n;
  return mean;
}

TEST(SoleContact, BlockOnSoleMatchesDirectFem) {
  Fixture f;
  auto world = make_world(*f.sole, 1.0, 0.0);
  const Eigen::Vector3d total = run(world, 0.6);
  const double weight_impulse = mass * g * dt;
  std::printf("%d contact nodes: total normal impulse %.12e N s, W dt = %.12e N s (rel %.2e)\n",
              f.sole->n_contacts(), total[0], weight_impulse, total[0] / weight_impulse - 1);
  EXPECT_NEAR(total[0] / weight_impulse, 1.0, 1e-6);

  // Every node on the ground: gap within the solver tolerance times dt.
  double max_gap = 0;
  for (int c = 0; c < f.sole->n_contacts(); ++c)
    max_gap = std::max(max_gap, std::abs(world.gap(c)));
  std::printf("max |gap| of the sole nodes: %.3e m\n", max_gap);
  EXPECT_LT(max_gap, 1e-8);

  // Direct FEM solve with the contact forces found.
  const auto& elasticity = f.sole->elasticity();
  fem::LinearElasticity direct(f.tria, elasticity.discretization(), f.materials);
  direct.setup({{0, nullptr}});
  direct.assemble();
  for (int k = 0; k < f.sole->n_contacts(); ++k) {
    const Eigen::Vector3d p = world.impulse(k) / dt; // (n, t1, t2) = (z, x, y)
    const auto& dofs = f.sole->contact_dofs()[k];
    direct.load()[dofs[0]] += p[1];
    direct.load()[dofs[1]] += p[2];
    direct.load()[dofs[2]] += p[0];
  }
  direct.solve();
  double max_difference = 0, max_u = 0;
  for (int k = 0; k < f.sole->n_contacts(); ++k) {
    const auto& dofs = f.sole->contact_dofs()[k];
    const Eigen::Vector3d fem_u(direct.solution()[dofs[0]], direct.solution()[dofs[1]],
                                direct.solution()[dofs[2]]);
    const Eigen::Vector3d loop_u(world.patch_displacement()[3 * k + 1],
                                 world.patch_displacement()[3 * k + 2],
                                 world.patch_displacement()[3 * k]);
    max_difference = std::max(max_difference, (fem_u - loop_u).cwiseAbs().maxCoeff());
    max_u = std::max(max_u, fem_u.cwiseAbs().maxCoeff());
  }
  std::printf("contact loop vs direct FEM: max |u| = %.4e m, max difference %.2e (rel %.2e)\n",
              max_u, max_difference, max_difference / max_u);
  EXPECT_LT(max_difference / max_u, 1e-8);
}

TEST(SoleContact, FrictionStateSetsCompressionStiffness) {
  Fixture f;
  const int n = f.sole->n_contacts();
  const double pressure = mass * g / (L * W), M = E * (1 - nu) / ((1 + nu) * (1 - 2 * nu));
  double e_a[2];
  for (const int sticking : {0, 1}) {
    auto world = make_world(*f.sole, sticking ? 1.0 : 0.0, 0.0);
    run(world, 0.6);
    e_a[sticking] = pressure / (mean_displacement(world, n).z() / T);
    double max_ratio = 0, max_tangential = 0;
    for (int c = 0; c < n; ++c) {
      const Eigen::Vector3d p = world.impulse(c);
      max_tangential = std::max(max_tangential, p.tail<2>().norm());
      if (p[0] > 0)
        max_ratio = std::max(max_ratio, p.tail<2>().norm() / p[0]);
    }
    std::printf("%s ground: E_a / E = %.4f; max |p_t| = %.3e N s, max |p_t| / p_n = %.3f\n",
                sticking ? "sticking" : "frictionless", e_a[sticking] / E, max_tangential,
                max_ratio);
    if (sticking)
      EXPECT_LT(max_ratio, 0.999); // strictly inside the cone: sticking
    else
      EXPECT_LT(max_tangential, 1e-14); // no friction at all
  }
  std::printf("bounds: E = 1, M / E = %.4f\n", M / E);
  EXPECT_GT(e_a[0], E);
  EXPECT_GT(e_a[1], e_a[0]);
  EXPECT_LT(e_a[1], M);
}

TEST(SoleContact, TangentialLoadHoldsOrSlides) {
  Fixture f;
  const int n = f.sole->n_contacts();
  const double force = 0.1 * mass * g;
  // Sticking: the sole shears; bonded-layer simple shear u = F t / (G A).
  auto sticking = make_world(*f.sole, 1.0, force);
  const Eigen::Vector3d total = run(sticking, 1.5);
  const double shear = -mean_displacement(sticking, n).x();
  const double G = E / (2 * (1 + nu)), reference = force * T / (G * L * W);
  std::printf("sticking: tangential impulse %.6e N s (F dt = %.6e); mean shear %.4e m, "
              "F t / (G A) = %.4e m (ratio %.4f); block speed %.2e m/s\n",
              total[1], force * dt, shear, reference, shear / reference,
              sticking.bodies[0].linear_velocity.norm());
  EXPECT_NEAR(-total[1] / (force * dt), 1.0, 1e-6);
  EXPECT_NEAR(shear / reference, 1.0, 0.10);
  EXPECT_LT(sticking.bodies[0].linear_velocity.norm(), 1e-6);

  // Frictionless: the block slides with a = F / m.
  auto sliding = make_world(*f.sole, 0.0, force);
  run(sliding, 0.5);
  const double v0 = sliding.bodies[0].linear_velocity.x();
  run(sliding, 0.5);
  const double acceleration = (sliding.bodies[0].linear_velocity.x() - v0) / 0.5;
  std::printf("frictionless: a = %.6f m/s^2, F / m = %.6f m/s^2\n", acceleration, force / mass);
  EXPECT_NEAR(acceleration / (force / mass), 1.0, 0.005);
}

} // namespace
} // namespace plantar::coupling
