// The Moreau-Jean theta method of the stepper and the Kelvin-Voigt sole (issue 8):
// - a joint spring (mass on the compliant ankle's vertical spring): the energy after N steps
//   against the theta method's closed-form amplification |lambda|^(2N),
//   |lambda|^2 = (1 + (1-theta)^2 w^2 dt^2) / (1 + theta^2 w^2 dt^2), and the order of
//   convergence to the exact motion (2 at theta = 1/2, 1 at theta = 1);
// - a box landing on an undamped and on a Kelvin-Voigt sole patch (no gravity): contact time,
//   maximum compression and exit velocity against the closed form of the (damped) oscillator
//   m x'' + k beta x' + k x = 0 that separates when the sole force k (x + beta x') is zero;
// - the theta-weighted impulses: the node impulse is dt ((1-theta) F_prev + theta F);
// - a theta per dof: passive joints (a light foot on a stiff damped spring) at passive_theta,
//   the rest at theta, against the same scheme written densely; theta = 1/2 rings there;
// - the steps allocate nothing (Eigen's malloc guard).
#define EIGEN_RUNTIME_NO_MALLOC
#include "coupling/pad_state.h"
#include "multibody/stepper.h"
#include "multibody/urdf_loader.h"
#include "tests/multibody/test_helpers.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

namespace plantar::multibody {
namespace {

using test::model_path;

struct SpringRun {
  double energy_ratio; // E_N / E_0
  double max_error;    // max |x_n - x(t_n)| over the run, m
  double max_off_axis; // max |pitch|, |roll|
};

/// 20 kg on the vertical spring k = 40 kN/m (no damping), x0 = 1 cm from equilibrium, for
/// @p duration seconds.
SpringRun run_spring(double theta, double dt, double duration) {
  ModelOptions options;
  options.floating_base = false;
  options.compliant_ankle.foot_links = {"foot"};
  options.compliant_ankle.linear_damping = 0.0;
  options.compliant_ankle.angular_damping = 0.0;
  const Model model = build_model_from_urdf(model_path("test/spring_foot.urdf"), options);
  const double m = 20.0, g = 9.81, k = options.compliant_ankle.linear_stiffness;
  const double omega = std::sqrt(k / m), z_eq = -m * g / k, x0 = 0.01;
  StepperParameters parameters;
  parameters.time_step = dt;
  parameters.theta = theta;
  parameters.passive_theta = theta; // the spring is a passive joint
  Stepper stepper(model, parameters);
  Eigen::VectorXd q(3), v = Eigen::VectorXd::Zero(3);
  q << z_eq + x0, 0.0, 0.0;
  const Eigen::VectorXd zero = Eigen::VectorXd::Zero(3);
  const double e0 = 0.5 * k * x0 * x0;
  SpringRun run{0, 0, 0};
  const int n_steps = static_cast<int>(std::lround(duration / dt));
  for (int n = 1; n <= n_steps; ++n) {
    stepper.step(q, v, zero, zero, zero);
    const double x = q[0] - z_eq;
    run.max_error = std::max(run.max_error, std::abs(x - x0 * std::cos(omega * n * dt)));
    run.max_off_axis = std::max({run.max_off_axis, std::abs(q[1]), std::abs(q[2])});
    run.energy_ratio = (0.5 * m * v[0] * v[0] + 0.5 * k * x * x) / e0;
  }
  return run;
}

TEST(ThetaMethod, JointSpringEnergyFollowsTheDiscreteAmplification) {
  const double k = 40000.0, m = 20.0, omega = std::sqrt(k / m), duration = 0.5;
  for (const double theta : {0.5, 0.6, 0.75, 1.0}) {
    for (const double dt : {2e-3, 1e-3}) {
      const SpringRun run = run_spring(theta, dt, duration);
      const double h2 = omega * omega * dt * dt;
      const double lambda2 =
          (1 + (1 - theta) * (1 - theta) * h2) / (1 + theta * theta * h2); // |lambda|^2
      const double expected = std::pow(lambda2, std::lround(duration / dt));
      std::printf("theta %.2f dt %.0e: E_N/E_0 = %.12f, closed form %.12f (rel. diff %.2e); "
                  "max |x - x(t)| = %.3e m; off-axis %.1e\n",
                  theta, dt, run.energy_ratio, expected, std::abs(run.energy_ratio / expected - 1),
                  run.max_error, run.max_off_axis);
      EXPECT_NEAR(run.energy_ratio / expected, 1.0, 1e-9);
      EXPECT_LT(run.max_off_axis, 1e-12);
    }
  }
}

TEST(ThetaMethod, JointSpringConvergesAtSecondOrderWithThetaOneHalf) {
  for (const double theta : {0.5, 1.0}) {
    const SpringRun coarse = run_spring(theta, 2.5e-4, 0.5);
    const SpringRun fine = run_spring(theta, 1.25e-4, 0.5);
    const double order = std::log2(coarse.max_error / fine.max_error);
    std::printf("theta %.1f: max error %.3e m (dt 0.25 ms), %.3e m (0.125 ms): order %.3f\n", theta,
                coarse.max_error, fine.max_error, order);
    if (theta == 0.5) {
      EXPECT_NEAR(order, 2.0, 0.1);
    } else {
      EXPECT_NEAR(order, 1.0, 0.15);
    }
  }
}

/// Two bodies on vertical prismatic joints in a chain: body 1 (m1) held by a PD spring-damper
/// (kp, kd) to the world, body 2 (m2) on a passive spring-damper (ks, ds) to body 1 (a light
/// foot under a compliant ankle). Linear: M = [m1 + m2, m2; m2, m2] in the relative
/// coordinates, gravity a constant force.
Model two_mass_chain(double m1, double m2, double ks, double ds) {
  Model model;
  model.add_world();
  const Eigen::Matrix3d small = 1e-3 * Eigen::Matrix3d::Identity();
  const int b1 = model.add_body(0, JointType::Prismatic, Eigen::Vector3d::UnitZ(), SE3(),
                                Inertia(m1, Eigen::Vector3d::Zero(), small), "lift", "leg");
  const int b2 = model.add_body(b1, JointType::Prismatic, Eigen::Vector3d::UnitZ(), SE3(),
                                Inertia(m2, Eigen::Vector3d::Zero(), small), "spring", "foot");
  model.passive_stiffness[model.idx_v[b2]] = ks;
  model.passive_damping[model.idx_v[b2]] = ds;
  model.actuated[model.idx_v[b2]] = false;
  model.finalize();
  return model;
}

/// The theta method with a theta per dof, written densely (Theta = diag(theta_j)):
///   v_T = (I - Theta) v + Theta v+,  M (v+ - v) = dt (f_g + K (r - x - Theta dt v_T) - D v_T),
///   x+ = x + dt v_T,
/// with K = diag(kp, ks), D = diag(kd, ds), r = (q_ref, 0) (q_ref constant, v_ref = 0). One
/// step maps (x, v) to (x+, v+) linearly plus a constant.
Eigen::Vector4d dense_theta_step(const Eigen::Matrix2d& mass, const Eigen::Vector2d& gravity_force,
                                 const Eigen::Matrix2d& k, const Eigen::Matrix2d& d,
                                 const Eigen::Vector2d& rest, const Eigen::Vector2d& theta,
                                 double dt, const Eigen::Vector4d& state) {
  const Eigen::Matrix2d th = theta.asDiagonal(), one_minus = Eigen::Matrix2d::Identity() - th;
  const Eigen::Vector2d x = state.head<2>(), v = state.tail<2>();
  // M v+ - M v = dt (f_g + K (r - x) - (K Theta dt + D) ((I - Theta) v + Theta v+))
  const Eigen::Matrix2d a = k * th * dt + d;
  const Eigen::Matrix2d lhs = mass + dt * a * th;
  const Eigen::Vector2d rhs = mass * v + dt * (gravity_force + k * (rest - x) - a * one_minus * v);
  const Eigen::Vector2d v_plus = lhs.partialPivLu().solve(rhs);
  Eigen::Vector4d next;
  next << x + dt * (one_minus * v + th * v_plus), v_plus;
  return next;
}

TEST(ThetaMethod, PassiveJointsTakeTheirOwnThetaAgainstTheDenseScheme) {
  // A 0.5 kg foot on a stiff damped spring (c dt / m = 60 at dt = 1 ms: the fast mode's
  // trapezoidal amplification is (1 - 30) / (1 + 30) = -0.935 per step) under a 30 kg leg on
  // its PD servo.
  const double m1 = 30.0, m2 = 0.5, ks = 40000.0, ds = 30000.0, kp = 2e5, kd = 2000.0;
  const double dt = 1e-3, g = 9.81, q_ref = 0.01;
  const Model model = two_mass_chain(m1, m2, ks, ds);
  Eigen::Matrix2d mass, k = Eigen::Matrix2d::Zero(), d = Eigen::Matrix2d::Zero();
  mass << m1 + m2, m2, m2, m2;
  k.diagonal() << kp, ks;
  d.diagonal() << kd, ds;
  const Eigen::Vector2d gravity_force(-(m1 + m2) * g, -m2 * g), rest(q_ref, 0.0);
  for (const double passive_theta : {0.5, 0.75, 1.0}) {
    StepperParameters parameters;
    parameters.time_step = dt;
    parameters.theta = 0.5;
    parameters.passive_theta = passive_theta;
    Stepper stepper(model, parameters);
    PdGains gains = PdGains::Zero(model);
    gains.stiffness[0] = kp;
    gains.damping[0] = kd;
    stepper.set_gains(gains);
    Eigen::VectorXd q = Eigen::VectorXd::Zero(2), v = Eigen::VectorXd::Zero(2);
    v[1] = 0.2; // the foot moving on its spring
    Eigen::Vector4d state(0.0, 0.0, 0.0, 0.2);
    const Eigen::VectorXd zero = Eigen::VectorXd::Zero(2);
    Eigen::VectorXd reference(2);
    reference << q_ref, 0.0;
    double max_difference = 0.0, scale = 0.0;
    int sign_changes = 0;
    double previous_rate = 0.0;
    for (int n = 0; n < 200; ++n) {
      stepper.step(q, v, zero, reference, zero);
      state = dense_theta_step(mass, gravity_force, k, d, rest, Eigen::Vector2d(0.5, passive_theta),
                               dt, state);
      Eigen::Vector4d mine;
      mine << q, v;
      max_difference = std::max(max_difference, (mine - state).cwiseAbs().maxCoeff());
      scale = std::max(scale, state.cwiseAbs().maxCoeff());
      if (n > 0 && n < 20 && v[1] * previous_rate < 0.0)
        ++sign_changes; // the foot's rate on its spring over the first 20 steps
      previous_rate = v[1];
    }
    std::printf("passive theta %.2f: max |stepper - dense| = %.2e (scale %.2e); the foot's "
                "velocity changes sign %d times in 20 steps\n",
                passive_theta, max_difference, scale, sign_changes);
    EXPECT_LT(max_difference, 1e-12 * std::max(1.0, scale));
    // The fast mode's factor per step, (1 + (1 - theta) lambda dt) / (1 - theta lambda dt) at
    // lambda dt = -60: -0.935 at 1/2 (rings for many steps), -0.30 at 3/4 (a few), 0.016 at 1.
    if (passive_theta == 0.5) {
      EXPECT_GE(sign_changes, 15);
    }
    if (passive_theta == 1.0) {
      EXPECT_LE(sign_changes, 1);
    }
  }
}

TEST(ThetaMethod, PassiveThetaDifferentFromThetaRefusesAPatchBelowThePassiveJoint) {
  const Model model = two_mass_chain(30.0, 0.5, 40000.0, 300.0);
  StepperParameters parameters;
  parameters.theta = 0.5;
  parameters.passive_theta = 1.0;
  Stepper stepper(model, parameters);
  coupling::PadState pad(1e-5 * Eigen::MatrixXd::Identity(3, 3));
  const Eigen::Matrix3Xd node = Eigen::Matrix3Xd::Zero(3, 1);
  EXPECT_THROW(stepper.add_deformable_patch(2, node, 0.5, pad), std::invalid_argument);
  stepper.add_deformable_patch(1, node, 0.5, pad); // above the passive joint
  parameters.passive_theta = 0.5;
  Stepper same(model, parameters);
  coupling::PadState pad2(1e-5 * Eigen::MatrixXd::Identity(3, 3));
  same.add_deformable_patch(2, node, 0.5, pad2);
}

struct Bounce {
  double exit_velocity;   // m/s, upward, after the contact
  double contact_time;    // s, steps with a non-zero sole force times dt
  double max_compression; // m, max of the node's normal displacement U_n
  double impulse_error;   // max | node impulse - dt ((1-theta) F_prev + theta F) |, N s
};

/// The 2 kg free box, gravity cancelled by a base force, lands at @p v0 (m/s, downward) on a
/// 4-node patch with normal compliance c per node (k = 4 / c in total) and damping @p beta.
Bounce run_bounce(double theta, double dt, double beta, double v0, double c) {
  const Model model = build_model_from_urdf(model_path("test/free_box.urdf"));
  StepperParameters parameters;
  parameters.time_step = dt;
  parameters.theta = theta;
  parameters.solver.solver = contact::ContactSolverType::gauss_seidel;
  parameters.solver.tolerance = 1e-12;
  parameters.solver.max_iterations = 1000;
  Stepper stepper(model, parameters);
  Eigen::Matrix3Xd nodes(3, 4);
  nodes << -0.2, 0.2, -0.2, 0.2, -0.1, -0.1, 0.1, 0.1, -0.05, -0.05, -0.05, -0.05;
  Eigen::MatrixXd compliance = Eigen::MatrixXd::Zero(12, 12);
  for (int j = 0; j < 4; ++j) {
    compliance.block<3, 3>(3 * j, 3 * j).diagonal() << 2 * c, 2 * c, c;
  }
  coupling::PadState pad(compliance);
  stepper.add_deformable_patch(1, nodes, 0.0, pad);
  pad.set_damping(beta);
  const double m = model.total_mass();
  Eigen::VectorXd q = model.neutral_configuration(), v = Eigen::VectorXd::Zero(6);
  q[2] = 0.05; // nodes on the ground
  v[2] = -v0;
  Eigen::VectorXd tau = Eigen::VectorXd::Zero(6);
  tau[2] = m * 9.81; // cancels gravity (base frame = world: no rotation)
  const double omega = std::sqrt(4.0 / (c * m));
  Bounce out{0, 0, 0, 0};
  Eigen::Vector3d f_prev = Eigen::Vector3d::Zero();
  const int n_steps = static_cast<int>(std::lround(3.0 * M_PI / omega / dt));
  const Eigen::VectorXd zero = Eigen::VectorXd::Zero(6);
  for (int n = 0; n < n_steps; ++n) {
    Eigen::internal::set_is_malloc_allowed(false);
    stepper.step(q, v, tau, q, zero);
    Eigen::internal::set_is_malloc_allowed(true);
    const Eigen::Vector3d f = pad.node_force(0);
    const Eigen::Vector3d expected = dt * ((1 - theta) * f_prev + theta * f);
    out.impulse_error = std::max(out.impulse_error, (stepper.node_impulse(0, 0) - expected).norm());
    f_prev = f;
    if (stepper.node_impulse(0, 0)[0] > 0) {
      out.contact_time += dt;
    }
    out.max_compression = std::max(out.max_compression, pad.displacement()[0]);
  }
  out.exit_velocity = v[2];
  return out;
}

/// Closed form of the Kelvin-Voigt landing: x'' + 2 zeta w x' + w^2 x = 0, x(0) = 0,
/// x'(0) = v0, until w^2 (x + beta x') = 0 (x the compression).
Bounce closed_form_bounce(double beta, double v0, double c, double m) {
  const double w = std::sqrt(4.0 / (c * m)), zeta = 0.5 * beta * w;
  const double wd = w * std::sqrt(1 - zeta * zeta);
  const auto x = [&](double t) { return v0 / wd * std::exp(-zeta * w * t) * std::sin(wd * t); };
  const auto xdot = [&](double t) {
    return v0 / wd * std::exp(-zeta * w * t) *
           (wd * std::cos(wd * t) - zeta * w * std::sin(wd * t));
  };
  const auto force = [&](double t) { return x(t) + beta * xdot(t); };
  // First zero of the force after t = 0 (positive until then), in (0, pi / wd].
  double lo = 1e-9 / w, hi = M_PI / wd;
  for (int it = 0; it < 200; ++it) {
    const double mid = 0.5 * (lo + hi);
    (force(mid) > 0 ? lo : hi) = mid;
  }
  // Maximum compression where x' = 0: tan(wd t) = wd / (zeta w).
  const double t_max = std::atan2(wd, zeta * w) / wd;
  return Bounce{-xdot(lo), lo, x(t_max), 0};
}

TEST(ThetaMethod, SoleLandingAgainstTheClosedFormOfTheKelvinVoigtOscillator) {
  const double v0 = 0.2, c = 2e-5, m = 2.0; // k = 2e5 N/m: w = 316 rad/s, contact ~10 ms
  for (const double beta : {0.0, 1e-3}) {
    const Bounce exact = closed_form_bounce(beta, v0, c, m);
    std::printf("beta %.0e s: closed form: exit %.6f m/s (e = %.4f), contact %.4f ms, max "
                "compression %.6e m\n",
                beta, exact.exit_velocity, exact.exit_velocity / v0, 1e3 * exact.contact_time,
                exact.max_compression);
    for (const double theta : {0.5, 1.0}) {
      double previous_error = 0;
      for (const double dt : {2e-4, 1e-4, 5e-5}) {
        const Bounce b = run_bounce(theta, dt, beta, v0, c);
        const double error = std::abs(b.exit_velocity - exact.exit_velocity) / v0;
        std::printf("  theta %.1f dt %.0e: exit %.6f m/s (error %.2e of v0), contact %.4f ms, "
                    "max compression %.6e m (rel. error %.2e), impulse split error %.1e N s\n",
                    theta, dt, b.exit_velocity, error, 1e3 * b.contact_time, b.max_compression,
                    std::abs(b.max_compression / exact.max_compression - 1), b.impulse_error);
        EXPECT_LT(b.impulse_error, 1e-15);
        EXPECT_NEAR(b.contact_time, exact.contact_time, 2 * dt);
        if (theta == 0.5) { // second order: within 1 % of v0 from w dt = 0.063
          EXPECT_LT(error, 0.01);
          EXPECT_NEAR(b.max_compression / exact.max_compression, 1.0, 0.01);
        } else { // first order: the numerical damping w dt / 2 per radian
          EXPECT_LT(error, 0.25);
        }
        if (previous_error > 0) {
          EXPECT_LT(error, 0.6 * previous_error) << "theta " << theta << " dt " << dt;
        }
        previous_error = error;
      }
    }
  }
}

TEST(ThetaMethod, BadParametersAreRejected) {
  const Model model = build_model_from_urdf(model_path("test/free_box.urdf"));
  StepperParameters parameters;
  parameters.theta = 0.4;
  EXPECT_THROW(Stepper(model, parameters), std::invalid_argument);
  parameters.theta = 1.1;
  EXPECT_THROW(Stepper(model, parameters), std::invalid_argument);
  parameters.theta = 1.0;
  parameters.passive_theta = 0.49;
  EXPECT_THROW(Stepper(model, parameters), std::invalid_argument);
  parameters.passive_theta = 1.0;
  parameters.theta = 0.5;
  Stepper stepper(model, parameters);
  Eigen::Matrix3Xd nodes = Eigen::Matrix3Xd::Zero(3, 1);
  coupling::PadState pad(1e-5 * Eigen::MatrixXd::Identity(3, 3));
  stepper.add_deformable_patch(1, nodes, 0.5, pad);
  EXPECT_THROW(pad.set_damping(-1e-3), std::invalid_argument);
  EXPECT_THROW(stepper.add_deformable_patch(1, Eigen::Matrix3Xd::Zero(3, 2), 0.5, pad),
               std::invalid_argument); // 2 nodes for a 1-node pad
  pad.set_damping(1e-3);
  EXPECT_THROW(
      pad.set_compliance(1e-5 * Eigen::MatrixXd::Identity(3, 3), Eigen::Vector3d(0, 0, 1e-4)),
      std::invalid_argument);
  EXPECT_THROW(coupling::PadState(Eigen::MatrixXd::Identity(3, 2)), std::invalid_argument);
  Eigen::Matrix3d asymmetric = Eigen::Matrix3d::Identity();
  asymmetric(0, 1) = 0.5;
  EXPECT_THROW(coupling::PadState{asymmetric}, std::invalid_argument);
}

} // namespace
} // namespace plantar::multibody
