// Kinematics and dynamics checked against independent computations:
// CRBA against M assembled column by column from RNEA, Jacobians and J-dot v against finite
// differences, the double pendulum against its closed-form M(q) and g(q), the kinetic energy
// against the sum over bodies, and no heap allocation inside the algorithms.
#define EIGEN_RUNTIME_NO_MALLOC
#include "multibody/center_of_mass.h"
#include "multibody/configuration.h"
#include "multibody/crba.h"
#include "multibody/data.h"
#include "multibody/jacobian.h"
#include "multibody/kinematics.h"
#include "multibody/rnea.h"
#include "multibody/urdf_loader.h"
#include "tests/multibody/test_helpers.h"

#include <Eigen/Eigenvalues>
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

namespace plantar::multibody {
namespace {

using test::model_path;
using test::random_configuration;
using test::random_vector;

Model load(const std::string& relative, bool floating) {
  ModelOptions options;
  options.floating_base = floating;
  return build_model_from_urdf(model_path(relative), options);
}

double max_abs(const Eigen::MatrixXd& m) {
  return m.cwiseAbs().maxCoeff();
}

class DynamicsOnModels : public ::testing::TestWithParam<std::pair<const char*, bool>> {};

TEST_P(DynamicsOnModels, CrbaEqualsRneaColumns) {
  const Model model = load(GetParam().first, GetParam().second);
  Data data(model);
  std::mt19937 rng(7);
  double worst = 0.0;
  for (int trial = 0; trial < 5; ++trial) {
    const Eigen::VectorXd q = random_configuration(model, rng);
    const Eigen::MatrixXd m = crba(model, data, q);
    const Eigen::VectorXd zero = Eigen::VectorXd::Zero(model.nv);
    const Eigen::VectorXd g = rnea(model, data, q, zero, zero);
    Eigen::MatrixXd m_rnea(model.nv, model.nv);
    for (int j = 0; j < model.nv; ++j) {
      m_rnea.col(j) = rnea(model, data, q, zero, Eigen::VectorXd::Unit(model.nv, j)) - g;
    }
    worst = std::max(worst, max_abs(m - m_rnea) / max_abs(m));
    EXPECT_LT(max_abs(m - m.transpose()), 1e-14 * max_abs(m));
    // Positive definite.
    EXPECT_GT(Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd>(m).eigenvalues().minCoeff(), 0.0);
  }
  std::printf("[%s] nv=%d max |M_crba - M_rnea| / max|M| = %.3e (tol 1e-12)\n", GetParam().first,
              model.nv, worst);
  EXPECT_LT(worst, 1e-12);
}

TEST_P(DynamicsOnModels, KineticEnergyEqualsSumOverBodies) {
  const Model model = load(GetParam().first, GetParam().second);
  Data data(model);
  std::mt19937 rng(11);
  const Eigen::VectorXd q = random_configuration(model, rng);
  const Eigen::VectorXd v = random_vector(model.nv, rng);
  const Eigen::MatrixXd m = crba(model, data, q);
  forward_kinematics(model, data, q, v);
  double sum = 0.0;
  for (int i = 1; i < model.n_bodies; ++i) {
    sum += 0.5 * data.v[i].dot(model.inertia[i].matrix() * data.v[i]);
  }
  const double quadratic = 0.5 * v.dot(m * v);
  std::printf("[%s] kinetic energy: 1/2 v'Mv = %.15g, sum 1/2 v_i' I_i v_i = %.15g\n",
              GetParam().first, quadratic, sum);
  EXPECT_NEAR(quadratic, sum, 1e-12 * std::abs(sum));
}

/// C(q, v) v from RNEA equals the Christoffel form from finite differences of M:
/// C v = dM/dt v - 1/2 d/dq (v' M v), checked through the power identity
/// v' (C v) = 1/2 v' (dM/dt) v (skew-symmetry of dM/dt - 2C).
TEST_P(DynamicsOnModels, CoriolisPowerMatchesMassMatrixRate) {
  const Model model = load(GetParam().first, GetParam().second);
  Data data(model);
  std::mt19937 rng(3);
  const Eigen::VectorXd q = random_configuration(model, rng);
  const Eigen::VectorXd v = random_vector(model.nv, rng);
  const Eigen::VectorXd zero = Eigen::VectorXd::Zero(model.nv);
  const Eigen::VectorXd g = rnea(model, data, q, zero, zero);
  const Eigen::VectorXd cv = rnea(model, data, q, v, zero) - g;
  const double h = 1e-6;
  Eigen::VectorXd qp(model.nq), qm(model.nq);
  integrate(model, q, v, h, qp);
  integrate(model, q, v, -h, qm);
  const Eigen::MatrixXd mp = crba(model, data, qp);
  const Eigen::MatrixXd mm = crba(model, data, qm);
  const double mdot = v.dot((mp - mm) * v) / (2.0 * h);
  std::printf("[%s] v'Cv = %.12g, 1/2 v'dM/dt v (FD) = %.12g\n", GetParam().first, v.dot(cv),
              0.5 * mdot);
  EXPECT_NEAR(v.dot(cv), 0.5 * mdot, 1e-6 * std::max(1.0, std::abs(mdot)));
}

TEST_P(DynamicsOnModels, JacobiansAndDriftAgainstFiniteDifferences) {
  const Model model = load(GetParam().first, GetParam().second);
  Data data(model);
  std::mt19937 rng(5);
  const Eigen::VectorXd q = random_configuration(model, rng);
  const Eigen::VectorXd v = random_vector(model.nv, rng);
  const int frame = static_cast<int>(model.frames.size()) - 1; // a leaf link
  const int body = model.frames[frame].body;
  const Eigen::Vector3d point(0.03, -0.02, 0.05);
  const double h = 1e-6;

  // Jacobian columns against finite differences of the point position.
  forward_kinematics(model, data, q);
  Eigen::MatrixXd jp(3, model.nv);
  point_jacobian(model, data, body, point, jp);
  Eigen::MatrixXd jf(6, model.nv);
  frame_jacobian(model, data, frame, jf);
  Eigen::MatrixXd jp_fd(3, model.nv), jf_fd_lin(3, model.nv);
  Eigen::VectorXd qp(model.nq), qm(model.nq);
  for (int k = 0; k < model.nv; ++k) {
    const Eigen::VectorXd e = Eigen::VectorXd::Unit(model.nv, k);
    integrate(model, q, e, h, qp);
    integrate(model, q, e, -h, qm);
    forward_kinematics(model, data, qp);
    const Eigen::Vector3d pp = data.oMi[body].act_point(point);
    const Eigen::Vector3d fp = frame_placement(model, data, frame).translation;
    forward_kinematics(model, data, qm);
    jp_fd.col(k) = (pp - data.oMi[body].act_point(point)) / (2 * h);
    jf_fd_lin.col(k) = (fp - frame_placement(model, data, frame).translation) / (2 * h);
  }
  const double jac_err = max_abs(jp - jp_fd) / max_abs(jp);
  const double frame_err = max_abs(jf.topRows(3) - jf_fd_lin) / max_abs(jf.topRows(3));

  // J-dot v: d/dt (J(q(t)) v) along q(t) = q (+) t v, central differences.
  forward_kinematics(model, data, q, v, Eigen::VectorXd::Zero(model.nv));
  const Eigen::Vector3d drift = point_drift_acceleration(model, data, body, point);
  const Vector6d frame_drift = frame_drift_acceleration(model, data, frame);
  integrate(model, q, v, h, qp);
  integrate(model, q, v, -h, qm);
  Eigen::MatrixXd jp_p(3, model.nv), jp_m(3, model.nv), jf_p(6, model.nv), jf_m(6, model.nv);
  forward_kinematics(model, data, qp);
  point_jacobian(model, data, body, point, jp_p);
  frame_jacobian(model, data, frame, jf_p);
  forward_kinematics(model, data, qm);
  point_jacobian(model, data, body, point, jp_m);
  frame_jacobian(model, data, frame, jf_m);
  const Eigen::Vector3d drift_fd = (jp_p - jp_m) * v / (2 * h);
  const Vector6d frame_drift_fd = (jf_p - jf_m) * v / (2 * h);
  const double drift_err = (drift - drift_fd).norm() / drift_fd.norm();
  const double frame_drift_err = (frame_drift - frame_drift_fd).norm() / frame_drift_fd.norm();

  std::printf("[%s] FD (h=1e-6) relative errors: point J %.2e, frame J %.2e, point Jdot v %.2e "
              "(|Jdot v| = %.4g), frame Jdot v %.2e (tol 1e-6)\n",
              GetParam().first, jac_err, frame_err, drift_err, drift_fd.norm(), frame_drift_err);
  EXPECT_LT(jac_err, 1e-6);
  EXPECT_LT(frame_err, 1e-6);
  EXPECT_LT(drift_err, 1e-6);
  EXPECT_LT(frame_drift_err, 1e-6);
}

TEST_P(DynamicsOnModels, CenterOfMassJacobianAgainstFiniteDifferences) {
  const Model model = load(GetParam().first, GetParam().second);
  Data data(model);
  std::mt19937 rng(9);
  const Eigen::VectorXd q = random_configuration(model, rng);
  forward_kinematics(model, data, q);
  const Eigen::Matrix3Xd jc = center_of_mass_jacobian(model, data);
  // Against central differences of the centre of mass along each velocity direction.
  Eigen::Matrix3Xd fd(3, model.nv);
  const double h = 1e-6;
  Eigen::VectorXd qp(model.nq), qm(model.nq);
  for (int k = 0; k < model.nv; ++k) {
    const Eigen::VectorXd e = Eigen::VectorXd::Unit(model.nv, k);
    integrate(model, q, e, h, qp);
    integrate(model, q, e, -h, qm);
    forward_kinematics(model, data, qp);
    const Eigen::Vector3d cp = center_of_mass(model, data);
    forward_kinematics(model, data, qm);
    fd.col(k) = (cp - center_of_mass(model, data)) / (2 * h);
  }
  const double err = max_abs(jc - fd) / max_abs(jc);
  std::printf("[%s] CoM Jacobian vs FD: relative error %.2e (tol 1e-6)\n", GetParam().first, err);
  EXPECT_LT(err, 1e-6);
  if (model.has_free_base()) {
    // Base translation moves the CoM rigidly: J_c (base linear block) = R_base.
    forward_kinematics(model, data, q);
    center_of_mass_jacobian(model, data);
    EXPECT_LT(max_abs(data.com_jacobian.leftCols(3) - data.oMi[1].rotation), 1e-14);
  }
}

TEST_P(DynamicsOnModels, AlgorithmsDoNotAllocate) {
  const Model model = load(GetParam().first, GetParam().second);
  Data data(model);
  std::mt19937 rng(1);
  const Eigen::VectorXd q = random_configuration(model, rng);
  const Eigen::VectorXd v = random_vector(model.nv, rng);
  const Eigen::VectorXd a = random_vector(model.nv, rng);
  Eigen::VectorXd q_next(model.nq);
  Eigen::MatrixXd j6(6, model.nv), j3(3, model.nv);
  Eigen::internal::set_is_malloc_allowed(false);
  rnea(model, data, q, v, a);
  nonlinear_effects(model, data, q, v);
  crba(model, data, q);
  forward_kinematics(model, data, q, v, a);
  frame_jacobian(model, data, 1, j6);
  body_jacobian_world(model, data, model.n_bodies - 1, j6);
  point_jacobian(model, data, model.n_bodies - 1, Eigen::Vector3d::Zero(), j3);
  center_of_mass_jacobian(model, data);
  integrate(model, q, v, 1e-3, q_next);
  Eigen::internal::set_is_malloc_allowed(true);
  SUCCEED();
}

INSTANTIATE_TEST_SUITE_P(Models, DynamicsOnModels,
                         ::testing::Values(std::make_pair("test/branched_robot.urdf", true),
                                           std::make_pair("test/branched_robot.urdf", false),
                                           std::make_pair("hrp2/hrp2.urdf", true)));

TEST(DoublePendulum, ClosedFormMassMatrixAndGravity) {
  const Model model = load("test/double_pendulum.urdf", false);
  ASSERT_EQ(model.nq, 2);
  ASSERT_EQ(model.nv, 2);
  Data data(model);
  // URDF values; the 0.2 kg tip on a fixed joint is merged into link 2.
  const double m1 = 1.5, l1 = 0.6, lc1 = 0.3, i1 = 0.05;
  const double m2_link = 1.0, l2 = 0.5, lc2_link = 0.25, i2_link = 0.03, m_tip = 0.2;
  const double m2 = m2_link + m_tip;
  const double lc2 = (m2_link * lc2_link + m_tip * l2) / m2;
  const double i2 = i2_link + m2_link * std::pow(lc2_link - lc2, 2) + m_tip * std::pow(l2 - lc2, 2);
  const double g = 9.81;
  double worst_m = 0.0, worst_g = 0.0;
  for (const auto& qv : {Eigen::Vector2d(0.0, 0.0), Eigen::Vector2d(0.3, -0.7),
                         Eigen::Vector2d(-1.2, 2.0), Eigen::Vector2d(2.9, 1.1)}) {
    const double q1 = qv[0], q2 = qv[1];
    Eigen::Matrix2d m_exact;
    m_exact(0, 0) =
        m1 * lc1 * lc1 + i1 + m2 * (l1 * l1 + lc2 * lc2 + 2 * l1 * lc2 * std::cos(q2)) + i2;
    m_exact(0, 1) = m_exact(1, 0) = m2 * (lc2 * lc2 + l1 * lc2 * std::cos(q2)) + i2;
    m_exact(1, 1) = m2 * lc2 * lc2 + i2;
    const Eigen::Vector2d g_exact(m1 * g * lc1 * std::sin(q1) +
                                      m2 * g * (l1 * std::sin(q1) + lc2 * std::sin(q1 + q2)),
                                  m2 * g * lc2 * std::sin(q1 + q2));
    const Eigen::MatrixXd m = crba(model, data, qv);
    const Eigen::VectorXd gq = gravity_torques(model, data, qv);
    worst_m = std::max(worst_m, max_abs(m - m_exact));
    worst_g = std::max(worst_g, (gq - g_exact).cwiseAbs().maxCoeff());
    std::printf("q = (%5.2f, %5.2f): M = [%.12f %.12f; . %.12f] exact [%.12f %.12f; . %.12f]; "
                "g = (%.10f, %.10f) exact (%.10f, %.10f)\n",
                q1, q2, m(0, 0), m(0, 1), m(1, 1), m_exact(0, 0), m_exact(0, 1), m_exact(1, 1),
                gq[0], gq[1], g_exact[0], g_exact[1]);
  }
  std::printf("max |M - M_exact| = %.2e kg m^2, max |g - g_exact| = %.2e N m (tol 1e-12)\n",
              worst_m, worst_g);
  EXPECT_LT(worst_m, 1e-12);
  EXPECT_LT(worst_g, 1e-12);
  // The fixed tip link is kept as a frame at the end of link 2.
  const int tip = model.frame_id("tip");
  forward_kinematics(model, data, Eigen::Vector2d(0.0, 0.0));
  EXPECT_LT((frame_placement(model, data, tip).translation - Eigen::Vector3d(0, 0, -1.1)).norm(),
            1e-15);
  // Limits: joint2 from the URDF, joint1 continuous (unbounded).
  EXPECT_EQ(model.lower_position_limit[1], -2.5);
  EXPECT_EQ(model.upper_position_limit[1], 2.5);
  EXPECT_EQ(model.effort_limit[1], 50.0);
  EXPECT_EQ(model.velocity_limit[1], 6.0);
  EXPECT_TRUE(std::isinf(model.upper_position_limit[0]));
}

TEST(Hrp2Model, StructureMassAndCenterOfMass) {
  const Model model = load("hrp2/hrp2.urdf", true);
  Data data(model);
  std::printf("HRP-2-like: nq = %d, nv = %d, bodies = %d, frames = %zu, mass = %.6f kg\n", model.nq,
              model.nv, model.n_bodies, model.frames.size(), model.total_mass());
  EXPECT_EQ(model.nv, 36);
  EXPECT_EQ(model.nq, 37);
  EXPECT_NEAR(model.total_mass(), 58.0, 1e-9); // the URDF's stated total
  // CoM height at the neutral configuration equals the composite inertia of the base from the
  // CRBA (an independent path: parallel-axis sums rather than a mass-weighted average).
  const Eigen::VectorXd q = model.neutral_configuration();
  crba(model, data, q);
  forward_kinematics(model, data, q);
  const Eigen::Vector3d com = center_of_mass(model, data);
  std::printf("neutral CoM = (%.6f, %.6f, %.6f) m relative to the waist; composite: (%.6f, %.6f, "
              "%.6f)\n",
              com.x(), com.y(), com.z(), data.composite[1].com.x(), data.composite[1].com.y(),
              data.composite[1].com.z());
  EXPECT_LT((com - data.composite[1].com).norm(), 1e-12);
  EXPECT_NEAR(data.composite[1].mass, 58.0, 1e-9);
  // M's base block is the total mass times identity.
  EXPECT_LT(max_abs(data.mass_matrix.topLeftCorner(3, 3) - 58.0 * Eigen::Matrix3d::Identity()),
            1e-12);
}

} // namespace
} // namespace plantar::multibody
