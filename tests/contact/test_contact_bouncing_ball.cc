// Bouncing ball with Newton restitution (paper eq. 5) under Moreau-Jean:
// apex heights h_k = e^(2k) h0 and rest after the Zeno time t0 (1+e)/(1-e),
// t0 = sqrt(2 h0/g) (validation.md).
#include "tests/contact/rigid_body_harness.h"

#include <cmath>
#include <cstdio>
#include <gtest/gtest.h>
#include <vector>

namespace pc = plantar::contact;
using plantar::contact::test::RigidWorld;

namespace {

struct BallRun {
  std::vector<double> apexes; // bottom height at each apex after a bounce, m
  double rest_time = -1.0;    // first time after which the ball stays in contact
  double final_height = 0.0, final_speed = 0.0, min_gap = 0.0;
  int n_unconverged = 0;
};

BallRun run_ball(double restitution, double h0, double dt, double t_end,
                 pc::ContactSolverType solver) {
  const double radius = 0.1, mass = 1.0;
  RigidWorld world;
  pc::test::RigidBody ball;
  ball.mass = mass;
  ball.principal_inertia.setConstant(0.4 * mass * radius * radius);
  ball.position = Eigen::Vector3d(0, 0, radius + h0);
  world.bodies.push_back(ball);
  pc::test::PointContact contact;
  contact.point = Eigen::Vector3d(0, 0, -radius);
  contact.friction = 0.5;
  world.contacts.push_back(contact);
  world.bias.restitution = restitution;
  world.settings.solver = solver;
  world.settings.tolerance = 1e-10;
  world.finalize();
  BallRun run;
  double previous_vz = 0.0;
  bool was_active = false;
  const int n_steps = static_cast<int>(std::lround(t_end / dt));
  for (int i = 0; i < n_steps; ++i) {
    const pc::SolverResult r = world.step(dt);
    if (!r.converged())
      ++run.n_unconverged;
    const double vz = world.bodies[0].linear_velocity.z();
    const double height = world.bodies[0].position.z() - radius;
    run.min_gap = std::min(run.min_gap, height);
    if (previous_vz > 0.0 && vz <= 0.0 && height > 1e-9)
      run.apexes.push_back(height);
    previous_vz = vz;
    const bool active = world.active(0) && std::abs(vz) < 1e-9; // 10x solver tolerance
    if (active && !was_active)
      run.rest_time = (i + 1) * dt;
    if (!active)
      run.rest_time = -1.0;
    was_active = active;
  }
  run.final_height = world.bodies[0].position.z() - radius;
  run.final_speed = world.bodies[0].linear_velocity.norm();
  return run;
}

} // namespace

class BouncingBall : public ::testing::TestWithParam<std::tuple<double, pc::ContactSolverType>> {};

TEST_P(BouncingBall, ApexHeightsAndZenoRest) {
  const double e = std::get<0>(GetParam());
  const pc::ContactSolverType solver = std::get<1>(GetParam());
  const double h0 = 1.0, g = 9.81, dt = 1e-4;
  const double t0 = std::sqrt(2.0 * h0 / g);
  const double t_zeno = t0 * (1.0 + e) / (1.0 - e);
  const BallRun run = run_ball(e, h0, dt, 1.25 * t_zeno + 0.2, solver);
  std::printf("e = %.1f (%s), dt = %.0e s\n", e, pc::to_string(solver), dt);
  ASSERT_GE(run.apexes.size(), 3u);
  for (int k = 1; k <= 3; ++k) {
    const double expected = std::pow(e, 2 * k) * h0;
    const double err = std::abs(run.apexes[k - 1] - expected) / expected;
    std::printf("  apex %d: %.6f m, expected e^%d h0 = %.6f m, relative error %.2e (tol 1e-2)\n", k,
                run.apexes[k - 1], 2 * k, expected, err);
    EXPECT_LE(err, 1e-2);
  }
  std::printf("  at rest from t = %.4f s; Zeno time t0 (1+e)/(1-e) = %.4f s (ratio %.4f, "
              "allowed [0.97, 1.01]); final height %.2e m (<= 1e-7 + g dt^2), speed %.2e m/s, min "
              "gap %.2e m, "
              "%d unconverged solves\n",
              run.rest_time, t_zeno, run.rest_time / t_zeno, run.final_height, run.final_speed,
              run.min_gap, run.n_unconverged);
  // It passes the accumulation point and stays at rest (no stalling, no jitter).
  EXPECT_GT(run.rest_time, 0.97 * t_zeno);
  EXPECT_LT(run.rest_time, 1.01 * t_zeno);
  // Contacts activate on the predicted gap gap + dt v_free <= margin (1e-7 m),
  // so the ball settles within margin + g dt^2 above the plane.
  EXPECT_LE(std::abs(run.final_height), 1e-7 + g * dt * dt);
  EXPECT_LE(run.final_speed, 1e-9);
  EXPECT_GE(run.min_gap, -1e-9); // impacts are caught before penetration
  EXPECT_EQ(run.n_unconverged, 0);
}

INSTANTIATE_TEST_SUITE_P(Restitution, BouncingBall,
                         ::testing::Combine(::testing::Values(0.5, 0.8),
                                            ::testing::Values(pc::ContactSolverType::gauss_seidel,
                                                              pc::ContactSolverType::admm)));
