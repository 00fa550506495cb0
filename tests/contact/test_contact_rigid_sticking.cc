// The direct solve on the warm start's active set for rigid contacts (rigid_sticking_solver.h):
// against a dense pseudo-inverse, the iterative solvers' unique net impulses, and the closed
// forms of a box resting on redundant contacts, sliding under a push, tipping onto an edge and
// landing flat.
#include "contact/contact_solver.h"
#include "tests/contact/random_problem.h"
#include "tests/contact/rigid_body_harness.h"

#include <Eigen/QR>
#include <cmath>
#include <cstdio>
#include <gtest/gtest.h>

namespace pc = plantar::contact;
using plantar::contact::test::RigidWorld;

namespace {

constexpr double kG = 9.81;
constexpr double kDt = 1e-3;

// A 2 kg box of 0.3 x 0.2 x 0.1 m resting on an n x n grid of its bottom face (redundant for
// n >= 2: 3 n^2 rows, rank 6), mu = 0.6.
RigidWorld resting_box(int n_per_side, bool direct) {
  RigidWorld world;
  const Eigen::Vector3d size(0.3, 0.2, 0.1);
  pc::test::RigidBody box;
  box.mass = 2.0;
  box.principal_inertia = pc::test::box_inertia(box.mass, size);
  box.position = Eigen::Vector3d(0, 0, 0.05);
  world.bodies.push_back(box);
  for (const Eigen::Vector3d& point : pc::test::box_bottom_grid(size, n_per_side)) {
    pc::test::PointContact contact;
    contact.point = point;
    contact.friction = 0.6;
    world.contacts.push_back(contact);
  }
  world.settings.solver = pc::ContactSolverType::automatic;
  world.settings.tolerance = 1e-10;
  world.settings.max_iterations = 4000;
  world.settings.sticking_direct = direct;
  world.finalize();
  return world;
}

// G^T p (m): the generalised impulse, unique even where p is not.
Eigen::VectorXd net_impulse(const pc::ContactProblem& problem, const Eigen::VectorXd& p) {
  return problem.rigid_factor.topRows(3 * problem.n_contacts).transpose() *
         p.head(3 * problem.n_contacts);
}

} // namespace

TEST(ContactRigidSticking, RestingBoxEqualsTheDensePseudoInverse) {
  // After two steps the box rests on 9 points; the step's problem is solved again from a warm
  // start that is off in the null space of W (internal forces) and in scale. The direct
  // candidate must be p0 + W^+ r, W^+ by a complete orthogonal decomposition of the dense W.
  RigidWorld world = resting_box(3, true);
  for (int i = 0; i < 2; ++i)
    ASSERT_TRUE(world.step(kDt).converged());
  const pc::ContactProblem& problem = world.problem();
  const int n = problem.n_contacts;
  ASSERT_EQ(n, 9);
  Eigen::VectorXd warm(3 * n);
  for (int k = 0; k < n; ++k) // uneven normal impulses with small, opposed tangential ones
    warm.segment<3>(3 * k) =
        Eigen::Vector3d(1.2 * 2.0 * kG * kDt / n * (1.0 + 0.3 * std::sin(1.7 * k)),
                        1e-4 * std::cos(2.3 * k), -1e-4 * std::sin(0.9 * k));
  Eigen::MatrixXd w;
  problem.assemble_delassus(w);
  Eigen::VectorXd target(3 * n); // v_free + b e_n
  target = problem.free_velocity.head(3 * n);
  for (int k = 0; k < n; ++k)
    target[3 * k] += problem.normal_bias[k];
  const Eigen::VectorXd r = -(target + w * warm);
  const Eigen::VectorXd expected =
      warm + Eigen::CompleteOrthogonalDecomposition<Eigen::MatrixXd>(w).pseudoInverse() * r;

  pc::ContactSolver solver(n, problem.rigid_rank());
  Eigen::VectorXd impulses = warm;
  const pc::SolverResult result = solver.solve(problem, world.settings, impulses);
  std::printf("resting box: direct %d (%s), residual %.2e, |p - (p0 + W^+ r)| %.2e\n",
              result.direct, pc::to_string(result.direct_attempt), result.residual,
              (impulses - expected).cwiseAbs().maxCoeff());
  ASSERT_TRUE(result.direct);
  EXPECT_LE(result.residual, world.settings.tolerance);
  EXPECT_LE((impulses - expected).cwiseAbs().maxCoeff(), 1e-9 * expected.cwiseAbs().maxCoeff());
  // The weight over one step, no tangential net impulse (closed form of the rest).
  double normal = 0.0;
  Eigen::Vector2d tangential = Eigen::Vector2d::Zero();
  for (int k = 0; k < n; ++k) {
    normal += impulses[3 * k];
    tangential += impulses.segment<2>(3 * k + 1);
  }
  EXPECT_NEAR(normal, 2.0 * kG * kDt, 1e-9);
  // To the velocity tolerance: |sum p_t| <= m tolerance.
  EXPECT_LE(tangential.norm(), 2.0 * world.settings.tolerance);
}

TEST(ContactRigidSticking, RestingBoxAcceptedEveryStep) {
  // 200 steps of rest on 3 x 3 and 4 x 4 grids: every solve direct, the net impulse that of
  // Gauss-Seidel/Newton without the direct solve, the box still.
  for (const int grid : {3, 4}) {
    RigidWorld direct = resting_box(grid, true);
    RigidWorld iterative = resting_box(grid, false);
    int n_direct = 0;
    double worst = 0.0;
    for (int i = 0; i < 200; ++i) {
      const pc::SolverResult a = direct.step(kDt);
      const pc::SolverResult b = iterative.step(kDt);
      ASSERT_TRUE(a.converged());
      ASSERT_TRUE(b.converged());
      n_direct += a.direct;
      Eigen::VectorXd pa(3 * direct.problem().n_contacts), pb(pa.size());
      for (int c = 0; c < direct.problem().n_contacts; ++c) {
        pa.segment<3>(3 * c) = direct.impulse(c);
        pb.segment<3>(3 * c) = iterative.impulse(c);
      }
      worst =
          std::max(worst, (net_impulse(direct.problem(), pa) - net_impulse(iterative.problem(), pb))
                              .cwiseAbs()
                              .maxCoeff());
    }
    std::printf("resting box on %d x %d: %d of 200 direct, net impulses differ by %.2e\n", grid,
                grid, n_direct, worst);
    EXPECT_EQ(n_direct, 200);
    EXPECT_LE(worst, 1e-9);
    EXPECT_LE(direct.bodies[0].linear_velocity.norm(), 1e-9);
  }
}

TEST(ContactRigidSticking, PushedBoxSlidesAsTheClosedForm) {
  // Sliding at 0.5 m/s under a push of 2 mu m g along x: a = F/m - mu g. Every contact is held
  // on its cone against the slip; the direct solve takes every step after the first.
  RigidWorld world = resting_box(2, true);
  pc::test::RigidBody& box = world.bodies[0];
  const double mu = 0.6, force = 2.0 * mu * box.mass * kG;
  box.linear_velocity = Eigen::Vector3d(0.5, 0.0, 0.0);
  box.force = Eigen::Vector3d(force, 0.0, 0.0);
  const int n_steps = 300;
  int n_direct = 0;
  for (int i = 0; i < n_steps; ++i) {
    const pc::SolverResult r = world.step(kDt);
    ASSERT_TRUE(r.converged());
    n_direct += r.direct;
  }
  const double expected = 0.5 + n_steps * kDt * (force / box.mass - mu * kG);
  std::printf("pushed box: %d of %d direct, v_x %.12f (closed form %.12f)\n", n_direct, n_steps,
              box.linear_velocity.x(), expected);
  EXPECT_GE(n_direct, n_steps - 1);
  EXPECT_NEAR(box.linear_velocity.x(), expected, 1e-8);
  EXPECT_LE(std::abs(box.linear_velocity.y()) + std::abs(box.linear_velocity.z()), 1e-8);
  EXPECT_LE(box.angular_velocity.norm(), 1e-7);
}

TEST(ContactRigidSticking, TippingBoxLiftsItsPulledContacts) {
  // A torque about y tips the resting box onto its +x edge: the other contacts are pulled (p_n <
  // 0 in the sticking candidate) and separate; the three left on the edge are collinear (G_U of
  // rank 5). The net impulse equals Newton's from zero at
  // tolerance 1e-12 (another solver, no warm start).
  RigidWorld world = resting_box(3, true);
  for (int i = 0; i < 2; ++i)
    ASSERT_TRUE(world.step(kDt).converged());
  // 4 N m against the weight's 2 kg g 0.15 m = 2.94 N m about the +x edge: the box tips about
  // it, lifting the six contacts at x < 0.15 m.
  world.bodies[0].torque = Eigen::Vector3d(0.0, 4.0, 0.0);
  const pc::SolverResult r = world.step(kDt);
  ASSERT_TRUE(r.converged());
  const pc::ContactProblem& problem = world.problem();
  const int n = problem.n_contacts;
  Eigen::VectorXd direct(3 * n);
  int n_lifted = 0;
  for (int c = 0; c < n; ++c) {
    direct.segment<3>(3 * c) = world.impulse(c);
    n_lifted += world.impulse(c)[0] == 0.0;
  }
  pc::ContactSolver newton(n, problem.rigid_rank());
  pc::SolverSettings settings = world.settings;
  settings.solver = pc::ContactSolverType::newton;
  settings.sticking_direct = false;
  settings.warm_start = false;
  settings.tolerance = 1e-12;
  Eigen::VectorXd reference = Eigen::VectorXd::Zero(3 * n);
  ASSERT_TRUE(newton.solve(problem, settings, reference).converged());
  const double difference =
      (net_impulse(problem, direct) - net_impulse(problem, reference)).cwiseAbs().maxCoeff();
  std::printf("tipping box: direct %d (%s), %d contacts lifted, net impulse against Newton "
              "%.2e\n",
              r.direct, pc::to_string(r.direct_attempt), n_lifted, difference);
  EXPECT_TRUE(r.direct);
  EXPECT_EQ(n_lifted, 6);
  EXPECT_LE(difference, 1e-9 * net_impulse(problem, reference).norm());
  EXPECT_GT(world.bodies[0].angular_velocity.y(), 0.0);
}

TEST(ContactRigidSticking, FlatLandingStopsTheBoxInOneStep) {
  // Touching the ground at 1 m/s with no warm start (no impulse yet): the contacts closing
  // under v_free stick; with restitution 0 the box stops, p_n summing to m (1 m/s + g dt).
  RigidWorld world = resting_box(3, true);
  pc::test::RigidBody& box = world.bodies[0];
  box.linear_velocity = Eigen::Vector3d(0.0, 0.0, -1.0);
  const pc::SolverResult r = world.step(kDt);
  ASSERT_TRUE(r.converged());
  double normal = 0.0;
  for (int c = 0; c < world.problem().n_contacts; ++c)
    normal += world.impulse(c)[0];
  std::printf("flat landing: direct %d (%s), v_z after %.2e, sum p_n %.12f\n", r.direct,
              pc::to_string(r.direct_attempt), box.linear_velocity.z(), normal);
  EXPECT_TRUE(r.direct);
  EXPECT_NEAR(box.linear_velocity.z(), 0.0, 1e-9);
  EXPECT_NEAR(normal, box.mass * (1.0 + kG * kDt), 1e-9);
}

TEST(ContactRigidSticking, NotTriedOnCompliantOrGeneralProblems) {
  // A problem with a compliant patch goes to StickingSolver (which needs patch levers: not
  // tried here), one with a general W is not tried either; the iteration solves both.
  for (const int n_patch : {4, 0}) {
    pc::ContactProblem problem = pc::test::random_problem(8, 6, n_patch, 1.0, 3);
    if (n_patch == 0)
      problem.general.set_dense(Eigen::MatrixXd::Identity(24, 24));
    pc::ContactSolver solver(8, 6);
    pc::SolverSettings settings;
    settings.solver = pc::ContactSolverType::gauss_seidel;
    settings.max_iterations = 5000;
    Eigen::VectorXd impulses = Eigen::VectorXd::Zero(24);
    for (int k = 0; k < 8; ++k)
      impulses[3 * k] = 0.1;
    const pc::SolverResult r = solver.solve(problem, settings, impulses);
    EXPECT_EQ(r.direct_attempt, pc::DirectAttempt::not_tried);
    EXPECT_TRUE(r.converged());
  }
}
