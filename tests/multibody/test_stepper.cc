// The time stepper: free fall against the closed-form discrete solution, a torque-free
// spinning body conserving momentum and energy, the compliant ankle's spring-damper against
// its analytic frequency and damping ratio, implicit against explicit stiff PD at dt = 5 ms,
// a humanoid standing on rigid contacts and a box on a compliant patch (with the contact
// solver of coupling/contact), and a step that allocates nothing.
#define EIGEN_RUNTIME_NO_MALLOC
#include "coupling/pad_state.h"
#include "multibody/crba.h"
#include "multibody/data.h"
#include "multibody/kinematics.h"
#include "multibody/rnea.h"
#include "multibody/stepper.h"
#include "multibody/urdf_loader.h"
#include "tests/multibody/test_helpers.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <vector>

namespace plantar::multibody {
namespace {

using test::model_path;

Eigen::Matrix3d base_rotation(const Eigen::VectorXd& q) {
  return Eigen::Quaterniond(q[6], q[3], q[4], q[5]).normalized().toRotationMatrix();
}

TEST(Stepper, FreeFallMatchesDiscreteClosedForm) {
  const Model model = build_model_from_urdf(model_path("test/free_box.urdf"));
  StepperParameters parameters;
  parameters.time_step = 1e-3;
  Stepper stepper(model, parameters);
  const double dt = parameters.time_step, g = 9.81, m = model.total_mass();
  Eigen::VectorXd q(7), v(6);
  const Eigen::Quaterniond orientation =
      Eigen::Quaterniond(Eigen::AngleAxisd(0.7, Eigen::Vector3d(1, 2, 3).normalized()));
  q << 0.1, -0.2, 10.0, orientation.x(), orientation.y(), orientation.z(), orientation.w();
  const Eigen::Vector3d p0 = q.head<3>();
  const Eigen::Vector3d v0_world(1.0, -0.5, 2.0);
  v.head<3>() = orientation.toRotationMatrix().transpose() * v0_world; // base frame
  v.tail<3>().setZero();
  const Eigen::VectorXd zero = Eigen::VectorXd::Zero(6);
  const int n_steps = 10000; // 10 s
  const double e0 = 0.5 * m * v0_world.squaredNorm() + m * g * p0.z();
  double worst_position = 0.0, worst_energy = 0.0;
  for (int n = 1; n <= n_steps; ++n) {
    stepper.step(q, v, zero, q, zero);
    const double t = n * dt;
    // Symplectic Euler with constant gravity: v_n exact, z_n = z(t) - g t dt / 2.
    const Eigen::Vector3d expected =
        p0 + v0_world * t + Eigen::Vector3d(0, 0, -0.5 * g * t * t - 0.5 * g * t * dt);
    worst_position = std::max(worst_position, (q.head<3>() - expected).norm());
    const Eigen::Vector3d v_world = base_rotation(q) * v.head<3>();
    const double energy = 0.5 * m * v_world.squaredNorm() + m * g * q[2];
    // Expected energy drift of the scheme: -m g^2 t dt / 2.
    worst_energy = std::max(worst_energy, std::abs(energy - e0 + 0.5 * m * g * g * t * dt));
  }
  const Eigen::Vector3d v_world = base_rotation(q) * v.head<3>();
  std::printf(
      "free fall 10 s, dt = 1 ms: max |p - p_discrete| = %.3e m (tol 1e-9); final "
      "horizontal momentum (%.15g, %.15g) vs (%.15g, %.15g) kg m/s; max |E - E0 + m g^2 t dt "
      "/ 2| = %.3e J (tol 1e-6; the drift itself is %.4f J at 10 s)\n",
      worst_position, m * v_world.x(), m * v_world.y(), m * v0_world.x(), m * v0_world.y(),
      worst_energy, 0.5 * m * g * g * 10.0 * dt);
  EXPECT_LT(worst_position, 1e-9);
  EXPECT_LT(worst_energy, 1e-6);
  EXPECT_NEAR(m * v_world.x(), m * v0_world.x(), 1e-10); // round-off over 1e4 steps
  EXPECT_NEAR(m * v_world.y(), m * v0_world.y(), 1e-10);
  EXPECT_LT(v.tail<3>().norm(), 1e-12); // no spin appears
  // The orientation is unchanged and the quaternion unit.
  EXPECT_LT(std::abs(q.segment<4>(3).norm() - 1.0), 1e-14);
}

struct SpinDrift {
  double energy;  // max relative |E - E0| / E0
  double angular; // max relative |L - L0| / |L0|
  double linear;  // max |p - p0| / |p0|
  double flip;    // min over time of the body y axis . initial y axis (a flip gives < 0)
};

SpinDrift spin(double dt, bool midpoint_bias = false) {
  ModelOptions options;
  options.gravity.setZero();
  const Model model = build_model_from_urdf(model_path("test/free_box.urdf"), options);
  StepperParameters parameters;
  parameters.time_step = dt;
  parameters.midpoint_bias = midpoint_bias;
  Stepper stepper(model, parameters);
  Data data(model);
  Eigen::VectorXd q = model.neutral_configuration(), v(6);
  v << 0.3, 0.1, -0.2, 0.05, 4.0, 0.0; // close to the intermediate axis: it tumbles
  const Eigen::VectorXd zero = Eigen::VectorXd::Zero(6);
  const Inertia& inertia = model.inertia[1];
  auto momentum = [&](const Eigen::VectorXd& qq, const Eigen::VectorXd& vv) {
    const Vector6d h = inertia * Vector6d(vv); // base frame, about the origin = CoM
    const Eigen::Matrix3d r = base_rotation(qq);
    return std::make_pair(Eigen::Vector3d(r * h.head<3>()), Eigen::Vector3d(r * h.tail<3>()));
  };
  const auto [p0, l0] = momentum(q, v);
  const double e0 = 0.5 * v.dot(inertia.matrix() * v);
  SpinDrift drift{0, 0, 0, 1};
  const int n_steps = static_cast<int>(std::lround(10.0 / dt));
  for (int n = 0; n < n_steps; ++n) {
    stepper.step(q, v, zero, q, zero);
    const auto [p, l] = momentum(q, v);
    drift.energy = std::max(drift.energy, std::abs(0.5 * v.dot(inertia.matrix() * v) - e0) / e0);
    drift.angular = std::max(drift.angular, (l - l0).norm() / l0.norm());
    drift.linear = std::max(drift.linear, (p - p0).norm() / p0.norm());
    drift.flip = std::min(drift.flip, base_rotation(q)(1, 1));
  }
  return drift;
}

TEST(Stepper, TorqueFreeSpinConservesMomentumAndEnergy) {
  const SpinDrift coarse = spin(1e-3);
  const SpinDrift fine = spin(5e-4);
  for (const auto& [name, d] : {std::make_pair("1 ms", coarse), std::make_pair("0.5 ms", fine)}) {
    std::printf("torque-free tumbling box, 10 s, dt = %s: max relative drift energy %.3e, "
                "angular momentum %.3e, linear momentum %.3e; min y.y0 = %.3f (tumbles)\n",
                name, d.energy, d.angular, d.linear, d.flip);
  }
  // The body really tumbles about its unstable intermediate axis.
  EXPECT_LT(coarse.flip, -0.5);
  // Bounds for dt = 1 ms over 10 s (|w| = 4 rad/s). The explicit gyroscopic and transport
  // terms of the Moreau-Jean step drift at first order: the base-frame linear velocity grows
  // by (1 + dt^2 |w|^2)^(1/2) per step, i.e. by about T dt |w|^2 / 2 = 8 % over T = 10 s.
  EXPECT_LT(coarse.energy, 0.1);
  EXPECT_LT(coarse.angular, 1e-2);
  EXPECT_LT(coarse.linear, 0.1);
  EXPECT_NEAR(coarse.linear, 10.0 * 1e-3 * 16.0 / 2.0, 0.01);
  // First order in dt: halving dt halves each drift.
  for (const double ratio :
       {coarse.energy / fine.energy, coarse.angular / fine.angular, coarse.linear / fine.linear}) {
    EXPECT_GT(ratio, 1.7);
    EXPECT_LT(ratio, 2.3);
  }
  // With the bias forces at the midpoint velocity (StepperParameters::midpoint_bias) the energy
  // drift becomes second order; the momentum direction error stays first order (q+ uses v+)
  // but is 4 (angular) to 70 (linear) times smaller.
  const SpinDrift mid_coarse = spin(1e-3, true);
  const SpinDrift mid_fine = spin(5e-4, true);
  for (const auto& [name, d] :
       {std::make_pair("1 ms", mid_coarse), std::make_pair("0.5 ms", mid_fine)}) {
    std::printf("midpoint bias, dt = %s: max relative drift energy %.3e, angular momentum %.3e, "
                "linear momentum %.3e; min y.y0 = %.3f\n",
                name, d.energy, d.angular, d.linear, d.flip);
  }
  EXPECT_LT(mid_coarse.flip, -0.5);
  EXPECT_LT(mid_coarse.energy, 1e-5);
  EXPECT_LT(mid_coarse.angular, 2e-3);
  EXPECT_LT(mid_coarse.linear, 2e-3);
  EXPECT_GT(mid_coarse.energy / mid_fine.energy, 3.5); // second order: ~4
}

/// Peak analysis of a sampled free vibration x(t) starting at a maximum with zero velocity:
/// damped frequency from the time of the next maximum, damping ratio from the logarithmic
/// decrement between the two maxima (peaks refined by a parabola through three samples).
struct Vibration {
  double omega_n;
  double zeta;
};

Vibration analyse(const std::vector<double>& x, double dt) {
  std::vector<std::pair<double, double>> maxima; // (time, value)
  maxima.emplace_back(0.0, x[0]);
  for (std::size_t k = 1; k + 1 < x.size() && maxima.size() < 2; ++k) {
    if (x[k] > x[k - 1] && x[k] >= x[k + 1]) {
      const double a = x[k - 1], b = x[k], c = x[k + 1];
      const double shift = 0.5 * (a - c) / (a - 2 * b + c);
      maxima.emplace_back((k + shift) * dt, b - 0.25 * (a - c) * shift);
    }
  }
  EXPECT_EQ(maxima.size(), 2u);
  const double period = maxima[1].first - maxima[0].first;
  const double delta = std::log(maxima[0].second / maxima[1].second);
  const double zeta = delta / std::sqrt(4 * M_PI * M_PI + delta * delta);
  const double omega_d = 2 * M_PI / period;
  return Vibration{omega_d / std::sqrt(1 - zeta * zeta), zeta};
}

TEST(CompliantAnkle, SpringDamperFrequencyAndDampingRatio) {
  ModelOptions options;
  options.floating_base = false;
  options.compliant_ankle.foot_links = {"foot"};
  options.compliant_ankle.angular_damping = 6.0; // N m s/rad: underdamped pitch/roll, to measure
  const Model model = build_model_from_urdf(model_path("test/spring_foot.urdf"), options);
  ASSERT_EQ(model.nv, 3);
  EXPECT_EQ(model.joint_names[1], "foot_compliance_z");
  EXPECT_EQ(model.joint_names[2], "foot_compliance_pitch");
  EXPECT_EQ(model.joint_names[3], "foot_compliance_roll");
  const double m = 20.0, i_yy = 0.3, g = 9.81;
  const double k = options.compliant_ankle.linear_stiffness,
               c = options.compliant_ankle.linear_damping;
  const double kr = options.compliant_ankle.angular_stiffness,
               cr = options.compliant_ankle.angular_damping;
  const double z_eq = -m * g / k; // static deflection under gravity

  StepperParameters parameters;
  parameters.time_step = 1e-5;
  Stepper stepper(model, parameters);
  Eigen::VectorXd q(3), v = Eigen::VectorXd::Zero(3);
  q << z_eq + 0.01, 0.02, 0.0;
  const Eigen::VectorXd zero = Eigen::VectorXd::Zero(3);
  std::vector<double> z{q[0] - z_eq}, pitch{q[1]};
  for (int n = 0; n < 40000; ++n) { // 0.4 s
    stepper.step(q, v, zero, zero, zero);
    z.push_back(q[0] - z_eq);
    pitch.push_back(q[1]);
  }
  const Vibration vz = analyse(z, parameters.time_step);
  const Vibration vp = analyse(pitch, parameters.time_step);
  const double wz = std::sqrt(k / m), zz = c / (2 * std::sqrt(k * m));
  const double wp = std::sqrt(kr / i_yy), zp = cr / (2 * std::sqrt(kr * i_yy));
  std::printf("vertical: omega_n %.5f rad/s (analytic %.5f, err %.2e), zeta %.5f (analytic %.5f, "
              "err %.2e)\n",
              vz.omega_n, wz, std::abs(vz.omega_n / wz - 1), vz.zeta, zz,
              std::abs(vz.zeta / zz - 1));
  std::printf("pitch:    omega_n %.5f rad/s (analytic %.5f, err %.2e), zeta %.5f (analytic %.5f, "
              "err %.2e); tolerance 1 %%\n",
              vp.omega_n, wp, std::abs(vp.omega_n / wp - 1), vp.zeta, zp,
              std::abs(vp.zeta / zp - 1));
  EXPECT_NEAR(vz.omega_n / wz, 1.0, 0.01);
  EXPECT_NEAR(vz.zeta / zz, 1.0, 0.01);
  EXPECT_NEAR(vp.omega_n / wp, 1.0, 0.01);
  EXPECT_NEAR(vp.zeta / zp, 1.0, 0.01);
  // The static deflection m g / k is reached exactly (the implicit step's fixed point is the
  // static one), here at dt = 1 ms after 3 s.
  StepperParameters coarse;
  coarse.time_step = 1e-3;
  Stepper coarse_stepper(model, coarse);
  q << 0.0, 0.0, 0.0;
  v.setZero();
  for (int n = 0; n < 3000; ++n) {
    coarse_stepper.step(q, v, zero, zero, zero);
  }
  std::printf("dt = 1 ms, after 3 s: deflection %.12f m, m g / k = %.12f m\n", q[0], z_eq);
  EXPECT_NEAR(q[0], z_eq, 1e-12);
}

/// Max |q - q_ref| of a PD-held pendulum over 2 s at dt = 5 ms; infinity on divergence.
double pd_pendulum(bool implicit, double kp, double kd, double q_ref, double* final_q) {
  ModelOptions options;
  options.floating_base = false;
  const Model model = build_model_from_urdf(model_path("test/pendulum.urdf"), options);
  StepperParameters parameters;
  parameters.time_step = 5e-3;
  parameters.implicit_gains = implicit;
  Stepper stepper(model, parameters);
  stepper.set_gains(PdGains::Uniform(model, kp, kd));
  Eigen::VectorXd q = Eigen::VectorXd::Zero(1), v = Eigen::VectorXd::Zero(1);
  const Eigen::VectorXd reference = Eigen::VectorXd::Constant(1, q_ref),
                        zero = Eigen::VectorXd::Zero(1);
  double worst = 0.0;
  try {
    for (int n = 0; n < 400; ++n) {
      stepper.step(q, v, zero, reference, zero);
      worst = std::max(worst, std::abs(q[0] - q_ref));
      if (!(worst < 1e6)) {
        return INFINITY;
      }
    }
  } catch (const std::runtime_error&) {
    return INFINITY; // non-finite state reported by the stepper
  }
  *final_q = q[0];
  return worst;
}

TEST(Stepper, StiffPdIsStableImplicitAndDivergesExplicit) {
  // Pendulum 1 kg at 0.5 m: I = 0.2501 kg m^2. kp = 5e4 N m/rad, kd = 500 N m s/rad:
  // omega = sqrt(kp / I) = 447 rad/s, omega dt = 2.2 > 2 and kd dt / I = 10: explicit diverges.
  const double kp = 5e4, kd = 500.0, q_ref = 0.5;
  double q_implicit = 0.0, q_explicit = 0.0;
  const double implicit_error = pd_pendulum(true, kp, kd, q_ref, &q_implicit);
  const double explicit_error = pd_pendulum(false, kp, kd, q_ref, &q_explicit);
  // Static equilibrium kp (q_ref - q) = m g l sin q, by Newton.
  double q_static = q_ref;
  for (int it = 0; it < 50; ++it) {
    const double f = kp * (q_ref - q_static) - 9.81 * 0.5 * std::sin(q_static);
    q_static -= f / (-kp - 9.81 * 0.5 * std::cos(q_static));
  }
  std::printf("stiff PD at dt = 5 ms: implicit max |q - q_ref| = %.4f rad, final q = %.12f "
              "(static equilibrium %.12f); explicit max |q - q_ref| = %g (diverged)\n",
              implicit_error, q_implicit, q_static, explicit_error);
  EXPECT_LT(implicit_error, q_ref + 1e-9); // never overshoots beyond the start
  EXPECT_NEAR(q_implicit, q_static, 1e-9);
  EXPECT_FALSE(explicit_error < 1e6);
  // The explicit version is fine with soft gains (omega dt = 0.14): it is the stiffness.
  double q_soft = 0.0;
  const double soft_error = pd_pendulum(false, 200.0, 10.0, q_ref, &q_soft);
  std::printf("soft PD (kp 200, kd 10), explicit: max |q - q_ref| = %.4f, final q = %.6f\n",
              soft_error, q_soft);
  EXPECT_LT(soft_error, 0.6);
}

/// HRP-2-like model standing on four corners per sole, joints held by stiff PD.
struct Standing {
  Standing() : model(build_model_from_urdf(model_path("hrp2/hrp2.urdf"))) {}
  Model model;
  void add_feet(Stepper& stepper) const {
    for (const char* sole : {"r_sole", "l_sole"}) {
      const Frame& frame = model.frames[model.frame_id(sole)];
      for (const double x : {-0.1086, 0.1086}) {
        for (const double y : {-0.069, 0.069}) {
          stepper.add_contact_point(frame.body, frame.placement.act_point(Eigen::Vector3d(x, y, 0)),
                                    0.8);
        }
      }
    }
  }
  Eigen::VectorXd standing_configuration() const {
    Data data(model);
    Eigen::VectorXd q = model.neutral_configuration();
    forward_kinematics(model, data, q);
    const SE3 sole = frame_placement(model, data, model.frame_id("r_sole"));
    q[2] = -sole.translation.z(); // soles on z = 0
    return q;
  }
};

class HumanoidStanding : public ::testing::TestWithParam<bool> {};

TEST_P(HumanoidStanding, OnRigidContactsWithoutAllocating) {
  Standing standing;
  const Model& model = standing.model;
  StepperParameters parameters;
  parameters.time_step = 1e-3;
  parameters.midpoint_bias = GetParam();
  std::printf("midpoint_bias = %d\n", static_cast<int>(GetParam()));
  Stepper stepper(model, parameters);
  stepper.set_gains(PdGains::Uniform(model, 1e4, 200.0));
  standing.add_feet(stepper);
  Eigen::VectorXd q = standing.standing_configuration();
  const Eigen::VectorXd q_ref = q;
  Eigen::VectorXd v = Eigen::VectorXd::Zero(model.nv);
  const Eigen::VectorXd zero = Eigen::VectorXd::Zero(model.nv);
  const double waist0 = q[2];
  int unconverged = 0;
  for (int n = 0; n < 1000; ++n) {
    if (n == 500) {
      Eigen::internal::set_is_malloc_allowed(false);
    }
    const StepReport report = stepper.step(q, v, zero, q_ref, zero);
    unconverged += report.solver.converged() ? 0 : 1;
    if (n == 999) {
      Eigen::internal::set_is_malloc_allowed(true);
      EXPECT_EQ(report.n_contacts, 8);
    }
  }
  const double weight = model.total_mass() * 9.81;
  const Eigen::Vector3d force = stepper.total_contact_force();
  std::printf("standing 1 s at dt = 1 ms: contact force (%.4f, %.4f, %.4f) N vs weight %.4f N "
              "(rel. err %.2e, tol 1e-3); waist height change %.3e m; |v| = %.3e; unconverged "
              "solves %d\n",
              force.x(), force.y(), force.z(), weight, std::abs(force.z() / weight - 1),
              q[2] - waist0, v.norm(), unconverged);
  EXPECT_NEAR(force.z() / weight, 1.0, 1e-3);
  EXPECT_LT(std::abs(force.x()) + std::abs(force.y()), 1e-3 * weight);
  EXPECT_LT(std::abs(q[2] - waist0), 1e-3);
  EXPECT_LT(v.norm(), 1e-3);
  EXPECT_EQ(unconverged, 0);
}

INSTANTIATE_TEST_SUITE_P(BiasAtStartOrMidpoint, HumanoidStanding, ::testing::Bool());

TEST(Stepper, BoxOnCompliantPatchSinksByTheSoleDeflection) {
  const Model model = build_model_from_urdf(model_path("test/free_box.urdf"));
  StepperParameters parameters;
  parameters.time_step = 1e-3;
  Stepper stepper(model, parameters);
  // Four nodes at the bottom corners, uncoupled compliance (m/N) per node, body frame.
  Eigen::Matrix3Xd nodes(3, 4);
  nodes << -0.2, 0.2, -0.2, 0.2, -0.1, -0.1, 0.1, 0.1, -0.05, -0.05, -0.05, -0.05;
  const double c_normal = 2e-5, c_tangent = 5e-5;
  Eigen::MatrixXd compliance = Eigen::MatrixXd::Zero(12, 12);
  for (int k = 0; k < 4; ++k) {
    compliance.block<3, 3>(3 * k, 3 * k).diagonal() << c_tangent, c_tangent, c_normal;
  }
  coupling::PadState pad(compliance);
  stepper.add_deformable_patch(1, nodes, 0.8, pad);
  Eigen::VectorXd q = model.neutral_configuration(), v = Eigen::VectorXd::Zero(6);
  q[2] = 0.06; // 1 cm drop
  const Eigen::VectorXd zero = Eigen::VectorXd::Zero(6);
  // The patch activates on landing (its storage is swapped in, not allocated): no step
  // allocates.
  Eigen::internal::set_is_malloc_allowed(false);
  for (int n = 0; n < 1500; ++n) {
    stepper.step(q, v, zero, q, zero);
  }
  Eigen::internal::set_is_malloc_allowed(true);
  const double weight = model.total_mass() * 9.81;
  const double deflection = c_normal * weight / 4.0; // per node
  const Eigen::VectorXd& u = pad.displacement();
  std::printf("box on a compliant patch: base z %.9f m, expected 0.05 - C_n F/4 = %.9f m "
              "(err %.2e m); node normal displacements %.4e %.4e %.4e %.4e (expected %.4e); "
              "contact force %.6f N vs weight %.6f N\n",
              q[2], 0.05 - deflection, q[2] - (0.05 - deflection), u[0], u[3], u[6], u[9],
              deflection, stepper.total_contact_force().z(), weight);
  EXPECT_NEAR(q[2], 0.05 - deflection, 0.01 * deflection);
  for (int k = 0; k < 4; ++k) {
    EXPECT_NEAR(u[3 * k], deflection, 0.01 * deflection);
  }
  EXPECT_NEAR(stepper.total_contact_force().z(), weight, 1e-3 * weight);
}

TEST(CompliantAnkle, HumanoidSettlesOnTheAnkleSprings) {
  ModelOptions options;
  options.compliant_ankle.foot_links = {"RLEG_LINK5", "LLEG_LINK5"};
  const Model model = build_model_from_urdf(model_path("hrp2/hrp2.urdf"), options);
  ASSERT_EQ(model.nv, 42);
  Standing standing;
  standing.model = model;
  StepperParameters parameters;
  parameters.time_step = 1e-3;
  Stepper stepper(model, parameters);
  stepper.set_gains(PdGains::Uniform(model, 1e4, 200.0));
  standing.add_feet(stepper);
  Eigen::VectorXd q = standing.standing_configuration();
  const Eigen::VectorXd q_ref = q;
  Eigen::VectorXd v = Eigen::VectorXd::Zero(model.nv);
  const Eigen::VectorXd zero = Eigen::VectorXd::Zero(model.nv);
  for (int n = 0; n < 3000; ++n) {
    stepper.step(q, v, zero, q_ref, zero);
  }
  // Each vertical spring carries half the weight above the feet, (M - 2 m_foot) g / 2, and is
  // compressed: the foot moves up relative to the ankle by that load / k.
  const double m_foot = model.inertia[model.body_id("RLEG_LINK5")].mass;
  const double load = (model.total_mass() - 2 * m_foot) * 9.81 / 2;
  const double expected = load / options.compliant_ankle.linear_stiffness;
  const double right = q[model.idx_q[model.joint_id("RLEG_LINK5_compliance_z")]];
  const double left = q[model.idx_q[model.joint_id("LLEG_LINK5_compliance_z")]];
  const double pitch = q[model.idx_q[model.joint_id("RLEG_LINK5_compliance_pitch")]];
  std::printf("HRP-2-like on compliant ankles after 3 s: vertical spring deflection right %.6f m, "
              "left %.6f m, expected (M - 2 m_foot) g / (2 k) = %.6f m (tol 0.1 %%); pitch %.5f "
              "rad; contact "
              "force %.3f N, |v| %.2e\n",
              right, left, expected, pitch, stepper.total_contact_force().z(), v.norm());
  EXPECT_NEAR(right / expected, 1.0, 1e-3);
  EXPECT_NEAR(left / expected, 1.0, 1e-3);
  EXPECT_NEAR(stepper.total_contact_force().z(), model.total_mass() * 9.81,
              1e-3 * model.total_mass() * 9.81);
  EXPECT_LT(v.norm(), 1e-3);
}

TEST(Stepper, BouncingBoxApexesAndTimeToRest) {
  // One frictionless contact point under the centre of the free box: a bouncing mass.
  // Newton restitution e: apexes h_k = e^(2k) h0; rest at t0 (1 + e) / (1 - e),
  // t0 = sqrt(2 h0 / g) (a Zeno accumulation the stepper must pass through).
  const Model model = build_model_from_urdf(model_path("test/free_box.urdf"));
  StepperParameters parameters;
  parameters.time_step = 1e-4;
  parameters.normal_bias.restitution = 0.5;
  Stepper stepper(model, parameters);
  stepper.add_contact_point(1, Eigen::Vector3d(0, 0, -0.05), 0.0);
  const double e = 0.5, h0 = 1.0, g = 9.81;
  Eigen::VectorXd q = model.neutral_configuration(), v = Eigen::VectorXd::Zero(6);
  q[2] = h0 + 0.05;
  const Eigen::VectorXd zero = Eigen::VectorXd::Zero(6);
  std::vector<double> apexes;
  double previous_vz = 0.0;
  const double t0 = std::sqrt(2 * h0 / g), t_rest = t0 * (1 + e) / (1 - e);
  const int n_steps = static_cast<int>((t_rest + 0.1) / parameters.time_step);
  for (int n = 0; n < n_steps; ++n) {
    stepper.step(q, v, zero, q, zero);
    if (previous_vz > 0.0 && v[2] <= 0.0) {
      apexes.push_back(q[2] - 0.05);
    }
    previous_vz = v[2];
  }
  ASSERT_GE(apexes.size(), 3u);
  for (int k = 0; k < 3; ++k) {
    const double exact = std::pow(e, 2 * (k + 1)) * h0;
    // Moreau-Jean resolves an impact to within one step of travel: tolerance dt sqrt(2 g h0).
    const double tolerance = parameters.time_step * std::sqrt(2 * g * h0);
    std::printf("apex %d: %.6f m, e^%d h0 = %.6f m (err %.2e m, tol %.2e m)\n", k + 1, apexes[k],
                2 * (k + 1), exact, apexes[k] - exact, tolerance);
    EXPECT_NEAR(apexes[k], exact, tolerance);
  }
  std::printf("at t_rest + 0.1 s = %.4f s: height %.3e m, v_z %.3e m/s, %zu apexes seen\n",
              t_rest + 0.1, q[2] - 0.05, v[2], apexes.size());
  EXPECT_LT(std::abs(q[2] - 0.05), 1e-4);
  EXPECT_LT(std::abs(v[2]), 1e-2);
}

TEST(Stepper, PatchComplianceIsRotatedIntoTheContactFrames) {
  // The box turned by 90 deg about z on a patch with anisotropic tangential compliance
  // (body x: 5e-5, body y: 1e-4 m/N) and pushed along world x by 5 N (below mu m g): each
  // sticking node carries -5/4 N along x, and the world x axis is the body y axis, so its
  // tangential displacement must be -c_y 5/4 = -1.25e-4 m (c_x would give half).
  const Model model = build_model_from_urdf(model_path("test/free_box.urdf"));
  StepperParameters parameters;
  parameters.time_step = 1e-3;
  Stepper stepper(model, parameters);
  Eigen::Matrix3Xd nodes(3, 4);
  nodes << -0.2, 0.2, -0.2, 0.2, -0.1, -0.1, 0.1, 0.1, -0.05, -0.05, -0.05, -0.05;
  const double c_x = 5e-5, c_y = 1e-4, c_z = 2e-5, push = 5.0;
  Eigen::MatrixXd compliance = Eigen::MatrixXd::Zero(12, 12);
  for (int k = 0; k < 4; ++k) {
    compliance.block<3, 3>(3 * k, 3 * k).diagonal() << c_x, c_y, c_z;
  }
  coupling::PadState pad(compliance);
  stepper.add_deformable_patch(1, nodes, 0.8, pad);
  const Eigen::Quaterniond yaw(Eigen::AngleAxisd(M_PI / 2, Eigen::Vector3d::UnitZ()));
  Eigen::VectorXd q(7), v = Eigen::VectorXd::Zero(6);
  q << 0.0, 0.0, 0.05, yaw.x(), yaw.y(), yaw.z(), yaw.w();
  Eigen::VectorXd tau = Eigen::VectorXd::Zero(6);
  const Eigen::VectorXd zero = Eigen::VectorXd::Zero(6);
  for (int n = 0; n < 2000; ++n) {
    // The push, a world-x force at the CoM given as a base-frame wrench, once the box has
    // settled (pushing while landing would let the lightly loaded nodes slip first, and the
    // split among the sticking nodes would depend on that history).
    tau.head<3>() = base_rotation(q).transpose() * Eigen::Vector3d(n >= 500 ? push : 0.0, 0, 0);
    stepper.step(q, v, tau, q, zero);
  }
  const Eigen::VectorXd& u = pad.displacement(); // [n, x, y] per node
  const double expected = -c_y * push / 4;
  std::printf("rotated patch: node x displacements %.4e %.4e %.4e %.4e m, expected -c_y F/4 = "
              "%.4e m (with c_x it would be %.4e); y displacements %.1e; |v| %.1e\n",
              u[1], u[4], u[7], u[10], expected, -c_x * push / 4, u[2], v.norm());
  for (int k = 0; k < 4; ++k) {
    EXPECT_NEAR(u[3 * k + 1], expected, 1e-3 * std::abs(expected));
    EXPECT_NEAR(u[3 * k + 2], 0.0, 1e-3 * std::abs(expected));
  }
}

} // namespace
} // namespace plantar::multibody
