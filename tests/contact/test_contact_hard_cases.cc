// Hard cases (validation.md): a box resting on 4 and 9 points (redundant
// contacts: no drift, report the internal force split), a 1000 kg box on a
// 1 kg box (ill-conditioned Delassus operator), the Painleve rod (mu = 5/3).
#include "contact/coulomb_cone.h"
#include "contact/local_contact_solve.h"
#include "tests/contact/rigid_body_harness.h"

#include <cmath>
#include <cstdio>
#include <gtest/gtest.h>

namespace pc = plantar::contact;
using plantar::contact::test::RigidWorld;

namespace {

constexpr double kG = 9.81;

void add_box(RigidWorld& world, double mass, const Eigen::Vector3d& size, double z, int n_side,
             int support_body, double support_top, double mu) {
  pc::test::RigidBody box;
  box.mass = mass;
  box.principal_inertia = pc::test::box_inertia(mass, size);
  box.position = Eigen::Vector3d(0, 0, z);
  world.bodies.push_back(box);
  for (const Eigen::Vector3d& point : pc::test::box_bottom_grid(size, n_side)) {
    pc::test::PointContact contact;
    contact.body_a = static_cast<int>(world.bodies.size()) - 1;
    contact.body_b = support_body;
    contact.plane_height = support_top;
    contact.point = point;
    contact.friction = mu;
    world.contacts.push_back(contact);
  }
}

} // namespace

class RestingBox : public ::testing::TestWithParam<std::tuple<int, pc::ContactSolverType>> {};

TEST_P(RestingBox, NoDriftOverTenSeconds) {
  const int n_side = std::get<0>(GetParam());
  const double dt = 1e-3, mass = 1.0;
  RigidWorld world;
  add_box(world, mass, Eigen::Vector3d(0.2, 0.2, 0.2), 0.1, n_side, -1, 0.0, 0.5);
  world.settings.solver = std::get<1>(GetParam());
  world.settings.tolerance = 1e-10;
  world.settings.max_iterations = 1000;
  world.finalize();
  const Eigen::Vector3d start = world.bodies[0].position;
  int n_unconverged = 0, total_iterations = 0;
  double max_drift = 0.0;
  for (int i = 0; i < 10000; ++i) {
    const pc::SolverResult r = world.step(dt);
    n_unconverged += !r.converged();
    total_iterations += r.iterations;
    max_drift = std::max(max_drift, (world.bodies[0].position - start).norm());
  }
  // Net impulse and moment about the CoM are determined; the split is not.
  const int n = static_cast<int>(world.contacts.size());
  double total = 0.0, p_min = 1e300, p_max = 0.0, tangential = 0.0;
  Eigen::Vector3d moment = Eigen::Vector3d::Zero();
  for (int c = 0; c < n; ++c) {
    const Eigen::Vector3d p = world.impulse(c);
    total += p[0];
    p_min = std::min(p_min, p[0]);
    p_max = std::max(p_max, p[0]);
    tangential = std::max(tangential, std::hypot(p[1], p[2]));
    moment += world.contacts[c].point.cross(world.frame(c).transpose() * p);
  }
  const double weight_impulse = mass * kG * dt;
  std::printf(
      "%d points, %s: max drift over 10 s %.2e m (tol 1e-6), %d unconverged, mean "
      "iterations %.2f; sum p_n = %.12e N s (m g dt = %.12e); split p_n in [%.4e, %.4e] N s "
      "(uniform %.4e), max |p_t| %.1e N s, moment %.1e N m s\n",
      n, pc::to_string(std::get<1>(GetParam())), max_drift, n_unconverged,
      total_iterations / 10000.0, total, weight_impulse, p_min, p_max, weight_impulse / n,
      tangential, moment.norm());
  EXPECT_LE(max_drift, 1e-6);
  EXPECT_EQ(n_unconverged, 0);
  // Impulse error of a solve at residual tol (m/s) is about m tol per contact.
  EXPECT_NEAR(total, weight_impulse, n * mass * world.settings.tolerance);
  EXPECT_LE(moment.norm(), 1e-9 * weight_impulse);
  EXPECT_GE(p_min, 0.0);
}

INSTANTIATE_TEST_SUITE_P(Points, RestingBox,
                         ::testing::Combine(::testing::Values(2, 3),
                                            ::testing::Values(pc::ContactSolverType::gauss_seidel,
                                                              pc::ContactSolverType::admm,
                                                              pc::ContactSolverType::automatic)));

TEST(HardCases, HeavyBoxOnLightBox) {
  // 1 kg box (0.2 m) on the ground, 1000 kg box (0.2 m) on top, 4 corner
  // contacts each; both start at rest in contact. 0.5 s at dt = 1 ms.
  const double dt = 1e-3;
  const Eigen::Vector3d size(0.2, 0.2, 0.2);
  struct Outcome {
    int n_unconverged = 0, n_direct = 0;
    double worst_residual = 0.0, worst_penetration = 0.0, mean_iterations = 0.0;
  } outcome[4];
  const int n_steps = 500;
  for (int s = 0; s < 4; ++s) { // GS, ADMM, auto; auto after the direct solve
    RigidWorld world;
    add_box(world, 1.0, size, 0.1, 2, -1, 0.0, 0.5);
    add_box(world, 1000.0, size, 0.3, 2, 0, 0.1, 0.5);
    world.settings.solver = s == 0   ? pc::ContactSolverType::gauss_seidel
                            : s == 1 ? pc::ContactSolverType::admm
                                     : pc::ContactSolverType::automatic;
    world.settings.tolerance = 1e-8;
    world.settings.max_iterations = 200;
    world.settings.sticking_direct = s == 3; // else the iterative solvers themselves
    world.finalize();
    for (int i = 0; i < n_steps; ++i) {
      const pc::SolverResult r = world.step(dt);
      outcome[s].n_unconverged += !r.converged();
      outcome[s].n_direct += r.direct;
      outcome[s].worst_residual = std::max(outcome[s].worst_residual, r.residual);
      outcome[s].mean_iterations += double(r.iterations) / n_steps;
      for (int c = 0; c < static_cast<int>(world.contacts.size()); ++c) {
        outcome[s].worst_penetration = std::max(outcome[s].worst_penetration, -world.gap(c));
      }
    }
    std::printf("heavy on light, %s%s (max 200 iterations, tol 1e-8 m/s): %d/%d steps "
                "unconverged, %d direct, worst residual %.2e m/s, mean iterations %.1f, worst "
                "penetration %.2e m\n",
                pc::to_string(world.settings.solver), s == 3 ? " after the direct solve" : "",
                outcome[s].n_unconverged, n_steps, outcome[s].n_direct, outcome[s].worst_residual,
                outcome[s].mean_iterations, outcome[s].worst_penetration);
  }
  // ADMM holds: every step converged, penetration bounded (under 1e-6 m).
  EXPECT_EQ(outcome[1].n_unconverged, 0);
  EXPECT_LE(outcome[1].worst_penetration, 1e-6);
  // Gauss-Seidel (measured): does not reach the tolerance within 200 sweeps
  // on most steps and its worst residual stays far above ADMM's.
  EXPECT_GT(outcome[0].n_unconverged, 250);
  EXPECT_GT(outcome[0].worst_residual, 100.0 * outcome[1].worst_residual);
  // Auto (GS, then Newton when GS slows down) holds like ADMM.
  EXPECT_EQ(outcome[2].n_unconverged, 0);
  EXPECT_LE(outcome[2].worst_penetration, 1e-6);
  // The direct solve on the warm start's active set (rigid_sticking_solver.h) takes the resting
  // stack: every step converged, all but the first few without an iteration.
  EXPECT_EQ(outcome[3].n_unconverged, 0);
  EXPECT_LE(outcome[3].worst_penetration, 1e-6);
  EXPECT_GE(outcome[3].n_direct, n_steps - 5);
}

TEST(HardCases, PainleveRod) {
  // Uniform rod, half-length l = 0.5 m, m = 1 kg, I = m l^2/3 about the
  // centre, lower end on the ground, angle theta = atan 2 (where the
  // acceleration-level problem first loses consistency, mu > 4/3), mu = 5/3.
  // In the direction where friction opposes sliding, the normal effective
  // inverse mass W_nn + mu W_nt d < 0.
  const double l = 0.5, mass = 1.0, mu = 5.0 / 3.0, dt = 1e-3;
  const double theta = std::atan(2.0);
  auto make = [&](double end_velocity_x, double spin) {
    RigidWorld world;
    pc::test::RigidBody rod;
    rod.mass = mass;
    rod.principal_inertia = Eigen::Vector3d(mass * l * l / 3.0, mass * l * l / 3.0, 1e-4);
    // Rod axis = body z, tilted by theta from the horizontal about -y.
    rod.orientation =
        Eigen::Quaterniond(Eigen::AngleAxisd(M_PI / 2 - theta, Eigen::Vector3d::UnitY()));
    rod.position = rod.orientation * Eigen::Vector3d(0, 0, l);
    rod.linear_velocity = Eigen::Vector3d(end_velocity_x, 0, 0);
    rod.angular_velocity = Eigen::Vector3d(0, spin, 0);
    rod.linear_velocity += rod.angular_velocity.cross(rod.position); // end point velocity set
    world.bodies.push_back(rod);
    pc::test::PointContact contact;
    contact.point = Eigen::Vector3d(0, 0, -l);
    contact.friction = mu;
    world.contacts.push_back(contact);
    world.settings.tolerance = 1e-10;
    world.finalize();
    return world;
  };
  // Which sliding direction makes the normal coefficient negative?
  RigidWorld probe = make(0.0, 0.0);
  probe.activation_margin = 1.0;
  probe.settings.solver = pc::ContactSolverType::gauss_seidel;
  probe.step(dt);
  const Eigen::Matrix3d w = probe.problem().diagonal_block(0);
  // Friction along -sign(slide) t1: den(d) = W_nn + mu W_n,t1 d.
  const double d_bad = w(0, 1) < 0.0 ? 1.0 : -1.0;
  const double den = w(0, 0) + mu * w(0, 1) * d_bad;
  std::printf(
      "rod: W_nn = %.4f, W_nt = %.4f, W_nn + mu W_nt d = %.4f (closed form (1 + 3 cos^2 - 3 mu "
      "sin cos)/m = %.4f)\n",
      w(0, 0), w(0, 1), den,
      (1 + 3 * std::cos(theta) * std::cos(theta) - 3 * mu * std::sin(theta) * std::cos(theta)) /
          mass);
  EXPECT_LT(den, 0.0);
  EXPECT_NEAR(
      den,
      (1 + 3 * std::cos(theta) * std::cos(theta) - 3 * mu * std::sin(theta) * std::cos(theta)) /
          mass,
      1e-9);
  for (const double spin_sign : {0.0, 1.0}) {
    // spin_sign = 1: the free motion lifts the end (q_n = 0.49 m/s). The
    // impulsive sliding solution p_n = -q_n/den then exists as well as
    // separation if the sliding speed exceeds 11.2 q_n (the tangential
    // velocity must still oppose the friction impulse): 10 m/s is used.
    // The end slides opposite to the friction direction d_bad.
    const double slide = -d_bad * (spin_sign == 0.0 ? 1.0 : 10.0);
    for (int s = 0; s < 2; ++s) {
      RigidWorld world = make(slide, 0.0);
      if (spin_sign != 0.0) {
        // Rotate so the end moves up at 0.5 m/s: omega_y with r_end = -(rod axis) l.
        const Eigen::Vector3d r_end = world.world_point(0) - world.bodies[0].position;
        const double omega = 0.5 / (-r_end.x()); // (omega y) x r: z-component = -omega r_x
        world.bodies[0].angular_velocity = Eigen::Vector3d(0, omega, 0);
        world.bodies[0].linear_velocity =
            Eigen::Vector3d(slide, 0, 0.5) - world.bodies[0].angular_velocity.cross(r_end);
      }
      world.settings.solver =
          s == 0 ? pc::ContactSolverType::gauss_seidel : pc::ContactSolverType::admm;
      world.settings.enumerate_local_solutions = true; // count the indeterminate contacts
      const pc::SolverResult r = world.step(dt);
      const Eigen::Vector3d p = world.impulse(0);
      // Local analysis of the same one-contact problem: all solutions.
      const Eigen::Matrix3d a = world.problem().diagonal_block(0);
      const Eigen::Vector3d q = world.problem().free_velocity.head<3>();
      const pc::LocalSolution local = pc::solve_local_contact(a, q, world.problem().normal_bias[0],
                                                              mu, Eigen::Vector3d::Zero());
      std::printf("rod %s, %s: q_n = %+.4f m/s, status %s, residual %.2e, nonunique flag %d, p = "
                  "(%.4e, %.4e, %.4e), local solutions %d\n",
                  spin_sign == 0.0 ? "pressed (q_n < 0)" : "lifting (q_n > 0)",
                  pc::to_string(world.settings.solver), q[0], pc::to_string(r.status), r.residual,
                  r.n_nonunique_local, p[0], p[1], p[2], local.n_solutions);
      EXPECT_TRUE(p.allFinite());
      EXPECT_NE(r.status, pc::SolverStatus::non_finite);
      // Whatever is returned satisfies the contact law to the reported residual or is flagged.
      const Eigen::Vector3d v = a * p + q;
      const double check =
          pc::contact_residual(p, v, world.problem().normal_bias[0], mu, 3.0 / a.trace());
      if (r.converged()) {
        EXPECT_LE(check, 1.01 * r.residual + 1e-15);
      }
      if (spin_sign != 0.0) {
        // Indeterminate: separation (p = 0) and an impulsive sliding solution both valid.
        EXPECT_GT(q[0], 0.0);
        EXPECT_GE(local.n_solutions, 2);
        if (s == 0) {
          EXPECT_GE(r.n_nonunique_local, 1) << "Gauss-Seidel flags the indeterminacy";
        }
      } else {
        EXPECT_LT(q[0], 0.0);
        EXPECT_GE(local.n_solutions, 1)
            << "velocity level: a solution exists (W positive definite)";
      }
      // A few more steps never produce NaN.
      for (int i = 0; i < 200; ++i) {
        const pc::SolverResult ri = world.step(dt);
        ASSERT_NE(ri.status, pc::SolverStatus::non_finite);
        ASSERT_TRUE(world.bodies[0].position.allFinite());
      }
    }
  }
}

TEST(HardCases, PositionCorrectionRemovesPenetration) {
  // A box starting 1 mm into the ground, beta = 0.2 (normal_bias). First
  // step: the constraint v_n >= -beta gap/dt is active, so gap_1 = (1 - beta)
  // gap_0 exactly. The push-out velocity stays in the body (Baumgarte-type
  // correction, documented): the penetration is gone after a few steps, the
  // box lifts by about the depth, lands exactly (speculative bias gap/dt)
  // and rests at gap 0.
  const double dt = 1e-3, beta = 0.2, depth = 1e-3;
  for (const auto type : {pc::ContactSolverType::gauss_seidel, pc::ContactSolverType::admm,
                          pc::ContactSolverType::automatic}) {
    RigidWorld world;
    add_box(world, 1.0, Eigen::Vector3d(0.2, 0.2, 0.2), 0.1 - depth, 2, -1, 0.0, 0.5);
    world.bias.position_correction = beta;
    world.settings.solver = type;
    world.settings.tolerance = 1e-12;
    world.settings.max_iterations = 2000;
    world.finalize();
    world.step(dt);
    const double first = world.gap(0);
    int steps_to_clear = 1;
    double max_lift = 0.0;
    for (int k = 2; k <= 500; ++k) {
      world.step(dt);
      if (world.gap(0) < -1e-12) // below round-off
        steps_to_clear = k;
      max_lift = std::max(max_lift, world.gap(0));
    }
    std::printf("%s: gap after 1 step %.12e m (expected %.12e), penetration cleared after %d "
                "steps, max lift %.3e m (depth %.1e), gap after 0.5 s %.2e m, speed %.2e m/s\n",
                pc::to_string(type), first, -depth * (1 - beta), steps_to_clear, max_lift, depth,
                world.gap(0), world.bodies[0].linear_velocity.norm());
    EXPECT_NEAR(first, -depth * (1.0 - beta), 1e-12);
    EXPECT_LE(steps_to_clear, 10);
    EXPECT_LE(max_lift, 2.0 * depth);
    EXPECT_NEAR(world.gap(0), 0.0, 1e-9);
    EXPECT_LE(world.bodies[0].linear_velocity.norm(), 1e-9);
  }
}
