// The stepper on a terrain (contact/terrain.h): a rigid block on an inclined plane against the
// incline's closed form (sticks for tan(alpha) < mu; else slides with acceleration
// g (sin(alpha) - mu cos(alpha)) along the line of greatest slope), and flat ground at a level
// z0 (the fast path) against the same box on z = 0 shifted by z0.
#include "contact/flat_terrain.h"
#include "contact/slope_terrain.h"
#include "multibody/stepper.h"
#include "multibody/urdf_loader.h"
#include "tests/multibody/test_helpers.h"

#include <Eigen/Geometry>
#include <cmath>
#include <cstdio>
#include <gtest/gtest.h>

namespace plantar::multibody {
namespace {

using test::model_path;

Eigen::Matrix3d base_rotation(const Eigen::VectorXd& q) {
  return Eigen::Quaterniond(q[6], q[3], q[4], q[5]).normalized().toRotationMatrix();
}

struct InclineRun {
  double acceleration = 0;       // along the line of greatest slope (down), m/s^2, fitted
  double max_sticking_speed = 0; // max |v| after 0.2 s (sticking), m/s
  double normal_force = 0;       // n . total contact force at the end, N
  double tangential_force = 0;   // d . total contact force at the end, N (up the slope: < 0)
  double off_plane = 0;          // max |n . (c - c0)| after 0.2 s: the box stays on the plane, m
  int unconverged = 0;
};

// The free box (2 kg, 0.4 x 0.2 x 0.1 m) with 4 contact points at its bottom corners on the
// plane through the origin turned by alpha about y (the ground falls towards +x), placed flat
// on it 0.1 mm above, released at rest and stepped for 1 s.
InclineRun incline(double alpha, double mu, double dt) {
  const Model model = build_model_from_urdf(model_path("test/free_box.urdf"));
  const contact::SlopeTerrain slope(alpha, M_PI / 2, Eigen::Vector3d::Zero());
  StepperParameters parameters;
  parameters.time_step = dt;
  parameters.solver.tolerance = 1e-10;
  Stepper stepper(model, parameters, slope);
  for (const double x : {-0.2, 0.2})
    for (const double y : {-0.1, 0.1})
      stepper.add_contact_point(1, Eigen::Vector3d(x, y, -0.05), mu);
  const Eigen::Quaterniond tilt(Eigen::AngleAxisd(alpha, Eigen::Vector3d::UnitY()));
  const Eigen::Vector3d normal = tilt * Eigen::Vector3d::UnitZ(); // (sin a, 0, cos a)
  const Eigen::Vector3d down = tilt * Eigen::Vector3d::UnitX();   // (cos a, 0, -sin a)
  Eigen::VectorXd q(7), v = Eigen::VectorXd::Zero(6);
  q.head<3>() = (0.05 + 1e-4) * normal;
  q.segment<4>(3) << tilt.x(), tilt.y(), tilt.z(), tilt.w();
  const Eigen::VectorXd zero = Eigen::VectorXd::Zero(6);
  InclineRun run;
  const int n_steps = static_cast<int>(std::lround(1.0 / dt));
  double v_start = 0, t_start = 0;
  Eigen::Vector3d c0 = Eigen::Vector3d::Zero();
  for (int n = 1; n <= n_steps; ++n) {
    const StepReport report = stepper.step(q, v, zero, q, zero);
    run.unconverged += !report.solver.converged();
    const double t = n * dt;
    const Eigen::Vector3d velocity = base_rotation(q) * v.head<3>();
    if (n == static_cast<int>(std::lround(0.2 / dt))) {
      v_start = down.dot(velocity);
      t_start = t;
      c0 = q.head<3>();
    }
    if (t > 0.2 + 0.5 * dt) {
      run.max_sticking_speed = std::max(run.max_sticking_speed, velocity.norm());
      run.off_plane = std::max(run.off_plane, std::abs(normal.dot(q.head<3>() - c0)));
    }
    if (n == n_steps)
      run.acceleration = (down.dot(velocity) - v_start) / (t - t_start);
  }
  const Eigen::Vector3d force = stepper.total_contact_force();
  run.normal_force = normal.dot(force);
  run.tangential_force = down.dot(force);
  return run;
}

TEST(StepperTerrain, BlockOnAnInclineFollowsTheClosedForm) {
  const double g = 9.81, m = 2.0, alpha = 20 * M_PI / 180, dt = 1e-3;
  // tan(20 deg) = 0.364: sticks with mu = 0.5, slides with mu = 0.2.
  const InclineRun stick = incline(alpha, 0.5, dt);
  std::printf("incline 20 deg, mu 0.5 (sticks): max |v| after 0.2 s %.2e m/s (tol 1e-6), normal "
              "force %.6f N (m g cos a = %.6f), friction %.6f N (-m g sin a = %.6f), off the "
              "plane %.1e m, unconverged %d\n",
              stick.max_sticking_speed, stick.normal_force, m * g * std::cos(alpha),
              stick.tangential_force, -m * g * std::sin(alpha), stick.off_plane, stick.unconverged);
  EXPECT_LT(stick.max_sticking_speed, 1e-6);
  EXPECT_NEAR(stick.normal_force, m * g * std::cos(alpha), 1e-6 * m * g);
  EXPECT_NEAR(stick.tangential_force, -m * g * std::sin(alpha), 1e-6 * m * g);
  EXPECT_EQ(stick.unconverged, 0);

  const double mu = 0.2;
  const InclineRun slide = incline(alpha, mu, dt);
  const double expected = g * (std::sin(alpha) - mu * std::cos(alpha));
  std::printf("incline 20 deg, mu 0.2 (slides): acceleration %.9f m/s^2, closed form g (sin a - "
              "mu cos a) = %.9f (rel err %.1e, tol 1e-6); normal force %.6f N (%.6f), friction "
              "%.6f N (-mu N = %.6f); off the plane %.1e m\n",
              slide.acceleration, expected, slide.acceleration / expected - 1, slide.normal_force,
              m * g * std::cos(alpha), slide.tangential_force, -mu * m * g * std::cos(alpha),
              slide.off_plane);
  // Moreau-Jean with the exact cone integrates a constant acceleration exactly; what is left
  // is the solver tolerance (1e-10 m/s per step over 800 steps).
  EXPECT_NEAR(slide.acceleration / expected, 1.0, 1e-6);
  EXPECT_NEAR(slide.normal_force, m * g * std::cos(alpha), 1e-6 * m * g);
  EXPECT_NEAR(slide.tangential_force, -mu * m * g * std::cos(alpha), 1e-6 * m * g);
  EXPECT_LT(slide.off_plane, 1e-6);
  EXPECT_EQ(slide.unconverged, 0);
}

TEST(StepperTerrain, LevelGroundIsTheFlatGroundShifted) {
  // The box dropped with a tilt onto z = 0.3 (the level fast path) and onto the default z = 0
  // from 0.3 m lower: the same motion, shifted by 0.3 m.
  const Model model = build_model_from_urdf(model_path("test/free_box.urdf"));
  StepperParameters parameters;
  const contact::FlatTerrain raised(0.3);
  Stepper on_raised(model, parameters, raised), on_default(model, parameters);
  for (Stepper* stepper : {&on_raised, &on_default})
    for (const double x : {-0.2, 0.2})
      for (const double y : {-0.1, 0.1})
        stepper->add_contact_point(1, Eigen::Vector3d(x, y, -0.05), 0.7);
  const Eigen::Quaterniond tilt(Eigen::AngleAxisd(0.2, Eigen::Vector3d(1, 1, 0).normalized()));
  Eigen::VectorXd q(7), v = Eigen::VectorXd::Zero(6);
  q << 0.0, 0.0, 0.2, tilt.x(), tilt.y(), tilt.z(), tilt.w();
  v << 0.3, 0.0, 0.0, 0.0, 0.0, 1.0;
  Eigen::VectorXd q_raised = q, v_raised = v;
  q_raised[2] += 0.3;
  const Eigen::VectorXd zero = Eigen::VectorXd::Zero(6);
  double worst = 0;
  for (int n = 0; n < 1000; ++n) {
    on_raised.step(q_raised, v_raised, zero, q_raised, zero);
    on_default.step(q, v, zero, q, zero);
    Eigen::VectorXd shifted = q_raised;
    shifted[2] -= 0.3;
    worst = std::max(
        {worst, (shifted - q).cwiseAbs().maxCoeff(), (v_raised - v).cwiseAbs().maxCoeff()});
  }
  std::printf("level ground z0 = 0.3 vs z = 0 shifted: max |dq|, |dv| %.1e (tol 1e-7)\n", worst);
  // The round-off of z +- 0.3 changes where the iterative contact solves stop, within their
  // tolerance (1e-8 m/s): the runs agree to that, not to round-off.
  EXPECT_LT(worst, 1e-7);
  EXPECT_GT(on_default.total_contact_force().z(), 0.0);
}

} // namespace
} // namespace plantar::multibody
