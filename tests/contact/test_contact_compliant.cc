// Compliant contact patch (paper eqs. 6, 7, 12): a rigid block of weight W
// pressed onto 8 x 8 sole nodes whose compliance is the Boussinesq-Cerruti
// half-space kernel (E = 4 MPa, the paper's choice; nu = 0.49), with a
// horizontal push of 0.1 W below the friction limit. At equilibrium:
//  * total normal impulse per step = W dt, tangential = -F_push dt;
//  * Gauss-Seidel and ADMM agree;
//  * the pressure distribution equals the direct dense solution of the
//    sticking, all-active linear system (rigid punch):
//        [ C    J ] [F]   [   0    ]
//        [ J^T  0 ] [d] = [ -f_ext ]
//    C the 3n x 3n compliance, J the block's contact Jacobian (3n x 6),
//    d its rigid displacement, f_ext its applied wrench (gravity + push),
//    solved with Eigen's dense LU.
#include "tests/contact/boussinesq_compliance.h"
#include "tests/contact/rigid_body_harness.h"

#include <Eigen/Dense>
#include <cmath>
#include <cstdio>
#include <gtest/gtest.h>

namespace pc = plantar::contact;
using plantar::contact::test::RigidWorld;

namespace {

constexpr double kG = 9.81;
constexpr int kSide = 8;
constexpr double kSpacing = 0.1 / kSide; // 0.1 m x 0.1 m sole patch
constexpr double kMass = 20.0, kYoung = 4e6, kPoisson = 0.49, kMu = 0.8, kDt = 5e-3;
constexpr double kPush = 0.1 * kMass * kG;

struct PatchRun {
  Eigen::VectorXd impulses; // 3n, contact order
  Eigen::MatrixXd jacobian; // 3n x 6 at the final configuration
  Eigen::Vector3d position;
  int n_unconverged = 0;
  double last_residual = 0.0;
  double final_speed = 0.0;
  double cube_normal = 0.0, cube_drift = 0.0; // optional rigid cube (mixed problem)
};

// with_cube: a 1 kg rigid cube on 4 rigid ground contacts is added to the same
// problem (contacts after the patch), so one solve handles both kinds.
PatchRun run_patch(pc::ContactSolverType solver, int n_steps, bool with_cube = false) {
  RigidWorld world;
  const Eigen::Vector3d size(0.1, 0.1, 0.05);
  pc::test::RigidBody block;
  block.mass = kMass;
  block.principal_inertia = pc::test::box_inertia(kMass, size);
  block.position = Eigen::Vector3d(0, 0, 0.5 * size.z());
  block.force = Eigen::Vector3d(kPush, 0, 0);
  world.bodies.push_back(block);
  const Eigen::MatrixXd nodes = pc::test::square_grid(kSide, kSpacing);
  for (int i = 0; i < nodes.rows(); ++i) {
    pc::test::PointContact contact;
    contact.point = Eigen::Vector3d(nodes(i, 0), nodes(i, 1), -0.5 * size.z());
    contact.friction = kMu;
    world.contacts.push_back(contact);
  }
  const int n_patch = static_cast<int>(nodes.rows());
  if (with_cube) {
    pc::test::RigidBody cube;
    cube.principal_inertia = pc::test::box_inertia(1.0, Eigen::Vector3d(0.2, 0.2, 0.2));
    cube.position = Eigen::Vector3d(0.5, 0.0, 0.1);
    world.bodies.push_back(cube);
    for (const Eigen::Vector3d& point :
         pc::test::box_bottom_grid(Eigen::Vector3d(0.2, 0.2, 0.2), 2)) {
      pc::test::PointContact contact;
      contact.body_a = 1;
      contact.point = point;
      contact.friction = kMu;
      world.contacts.push_back(contact);
    }
  }
  world.set_patch(pc::test::boussinesq_compliance(nodes, kSpacing, kYoung, kPoisson));
  world.settings.solver = solver;
  world.settings.tolerance = 1e-10;
  world.settings.max_iterations = 5000;
  world.finalize();
  PatchRun run;
  for (int i = 0; i < n_steps; ++i) {
    const pc::SolverResult r = world.step(kDt);
    run.n_unconverged += !r.converged();
    run.last_residual = r.residual;
  }
  const int n = n_patch;
  if (with_cube) {
    for (int c = n_patch; c < n_patch + 4; ++c)
      run.cube_normal += world.impulse(c)[0];
    run.cube_drift = (world.bodies[1].position - Eigen::Vector3d(0.5, 0.0, 0.1)).norm();
  }
  run.impulses.resize(3 * n);
  run.jacobian.resize(3 * n, 6);
  const pc::test::RigidBody& b = world.bodies[0];
  for (int c = 0; c < n; ++c) {
    run.impulses.segment<3>(3 * c) = world.impulse(c);
    const Eigen::Matrix3d f = world.frame(c);
    const Eigen::Vector3d r = world.world_point(c) - b.position;
    Eigen::Matrix3d skew;
    skew << 0, -r.z(), r.y(), r.z(), 0, -r.x(), -r.y(), r.x(), 0;
    run.jacobian.block<3, 3>(3 * c, 0) = f;
    run.jacobian.block<3, 3>(3 * c, 3) = -f * skew;
  }
  run.position = b.position;
  run.final_speed = b.linear_velocity.norm() + b.angular_velocity.norm();
  return run;
}

} // namespace

TEST(ContactCompliant, BoussinesqPatchUnderRigidBlock) {
  const int n = kSide * kSide, n_steps = 200;
  const Eigen::MatrixXd nodes = pc::test::square_grid(kSide, kSpacing);
  const Eigen::MatrixXd compliance =
      pc::test::boussinesq_compliance(nodes, kSpacing, kYoung, kPoisson);
  // The kernel is symmetric positive definite (a physical compliance).
  EXPECT_LE((compliance - compliance.transpose()).norm(), 1e-15 * compliance.norm());
  EXPECT_EQ(Eigen::LLT<Eigen::MatrixXd>(compliance).info(), Eigen::Success);

  const PatchRun gs = run_patch(pc::ContactSolverType::gauss_seidel, n_steps);
  const PatchRun admm = run_patch(pc::ContactSolverType::admm, n_steps);
  for (const PatchRun* run : {&gs, &admm}) {
    double normal = 0.0, tangential_x = 0.0, tangential_y = 0.0, ratio = 0.0;
    for (int c = 0; c < n; ++c) {
      normal += run->impulses[3 * c];
      tangential_x += run->impulses[3 * c + 1];
      tangential_y += run->impulses[3 * c + 2];
      ratio = std::max(ratio, std::hypot(run->impulses[3 * c + 1], run->impulses[3 * c + 2]) /
                                  run->impulses[3 * c]);
    }
    std::printf("%s: %d unconverged of %d steps, last residual %.2e m/s, final speed %.2e; "
                "sum p_n = %.10e N s (W dt = %.10e), sum p_x = %.10e (-F dt = %.10e), sum p_y = "
                "%.1e, max |p_t|/p_n = %.3f (mu = %.2f: all stick), sink %.4e m\n",
                run == &gs ? "gauss_seidel" : "admm", run->n_unconverged, n_steps,
                run->last_residual, run->final_speed, normal, kMass * kG * kDt, tangential_x,
                -kPush * kDt, tangential_y, ratio, kMu, 0.025 - run->position.z());
    EXPECT_EQ(run->n_unconverged, 0);
    EXPECT_NEAR(normal, kMass * kG * kDt, 1e-7 * kMass * kG * kDt);
    EXPECT_NEAR(tangential_x, -kPush * kDt, 1e-7 * kMass * kG * kDt);
    EXPECT_LE(ratio, kMu);
  }
  const double agree = (gs.impulses - admm.impulses).norm() / admm.impulses.norm();
  std::printf("|p_gs - p_admm| / |p| = %.2e (tol 1e-6)\n", agree);
  EXPECT_LE(agree, 1e-6);

  // Dense reference: [C J; J^T 0] [F; d] = [0; -f_ext], Eigen full-pivot LU.
  Eigen::MatrixXd kkt = Eigen::MatrixXd::Zero(3 * n + 6, 3 * n + 6);
  kkt.topLeftCorner(3 * n, 3 * n) = compliance;
  kkt.topRightCorner(3 * n, 6) = admm.jacobian;
  kkt.bottomLeftCorner(6, 3 * n) = admm.jacobian.transpose();
  Eigen::VectorXd rhs = Eigen::VectorXd::Zero(3 * n + 6);
  rhs.segment<3>(3 * n) = -Eigen::Vector3d(kPush, 0.0, -kMass * kG);
  const Eigen::VectorXd solution = kkt.fullPivLu().solve(rhs);
  const Eigen::VectorXd reference = solution.head(3 * n) * kDt; // impulses per step
  const double kkt_residual = (kkt * solution - rhs).norm() / rhs.norm();
  const double err =
      (admm.impulses - reference).lpNorm<Eigen::Infinity>() / reference.lpNorm<Eigen::Infinity>();
  const double err_gs =
      (gs.impulses - reference).lpNorm<Eigen::Infinity>() / reference.lpNorm<Eigen::Infinity>();
  // Show the punch profile along the middle row: edges carry more than the centre.
  std::printf("dense LU reference (residual %.1e): p_n along row %d, simulated / dense:\n",
              kkt_residual, kSide / 2);
  for (int j = 0; j < kSide; ++j) {
    const int c = (kSide / 2) * kSide + j;
    std::printf("  node %2d: %.6e / %.6e N s\n", c, admm.impulses[3 * c], reference[3 * c]);
  }
  std::printf("max |p - p_dense| / max |p_dense|: admm %.2e, gauss_seidel %.2e (tol 1e-4)\n", err,
              err_gs);
  EXPECT_LE(err, 1e-4);
  EXPECT_LE(err_gs, 1e-4);
  // Corner/centre ratio of the punch profile: check that edges carry more.
  EXPECT_GT(reference[0], reference[3 * ((kSide / 2) * kSide + kSide / 2)]);
}

TEST(ContactCompliant, MixedRigidAndCompliantContactsInOneProblem) {
  // The sole patch and a separate rigid cube (4 rigid contacts) in one
  // problem (rank 12: two bodies): the two are mechanically independent, so
  // the patch impulses must equal those of the patch-only run and the cube
  // must carry exactly its weight and not drift.
  const int n_steps = 200;
  for (const auto type : {pc::ContactSolverType::gauss_seidel, pc::ContactSolverType::admm}) {
    const PatchRun alone = run_patch(type, n_steps);
    const PatchRun mixed = run_patch(type, n_steps, true);
    const double diff = (mixed.impulses - alone.impulses).norm() / alone.impulses.norm();
    std::printf("%s mixed problem: %d unconverged; patch impulses vs patch alone %.2e (tol 1e-6); "
                "cube sum p_n = %.10e N s (m g dt = %.10e), cube drift %.2e m\n",
                pc::to_string(type), mixed.n_unconverged, diff, mixed.cube_normal, kG * kDt,
                mixed.cube_drift);
    EXPECT_EQ(mixed.n_unconverged, 0);
    EXPECT_LE(diff, 1e-6);
    EXPECT_NEAR(mixed.cube_normal, kG * kDt, 4 * 1e-10 * 1.0 + 1e-12);
    EXPECT_LE(mixed.cube_drift, 1e-9);
  }
}
