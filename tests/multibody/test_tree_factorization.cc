// The tree factorization A = L^T D L (multibody/tree_factorization.h, Featherstone 2005)
// against Eigen's dense LLT on M(q) + diagonal at random configurations of the HRP-2-like model
// (free base, compliant ankles or not), the branched test model (fixed and free base) and the
// double pendulum: solves, half solves, the reconstruction L^T D L, the sparsity of a body
// Jacobian's half solve, the refusal of an indefinite matrix, and no allocation; then the
// stepper with it against the stepper with the dense Cholesky on the same trajectories (the
// HRP-2-like robot dropped onto 16 sole points, and the branched robot touching the ground
// with every body, where the contact rows keep all nv columns).
#define EIGEN_RUNTIME_NO_MALLOC
#include "multibody/crba.h"
#include "multibody/data.h"
#include "multibody/jacobian.h"
#include "multibody/kinematics.h"
#include "multibody/stepper.h"
#include "multibody/tree_factorization.h"
#include "multibody/urdf_loader.h"
#include "tests/multibody/test_helpers.h"

#include <Eigen/Cholesky>
#include <gtest/gtest.h>

#include <cstdio>
#include <string>
#include <tuple>

namespace plantar::multibody {
namespace {

using test::model_path;
using test::random_configuration;
using test::random_vector;

Model load(const std::string& relative, bool floating, bool compliant_ankles) {
  ModelOptions options;
  options.floating_base = floating;
  if (compliant_ankles) {
    options.compliant_ankle.foot_links = {"RLEG_LINK5", "LLEG_LINK5"};
  }
  return build_model_from_urdf(model_path(relative), options);
}

double relative_error(const Eigen::MatrixXd& x, const Eigen::MatrixXd& reference) {
  return (x - reference).norm() / reference.norm();
}

class TreeFactorizationOnModels
    : public ::testing::TestWithParam<std::tuple<const char*, bool, bool>> {
protected:
  Model model_ = load(std::get<0>(GetParam()), std::get<1>(GetParam()), std::get<2>(GetParam()));
};

// A = M(q) + diag(c), c in [0, 10): the stepper's M + theta dt D + theta^2 dt^2 K has this form.
Eigen::MatrixXd random_tree_matrix(const Model& model, std::mt19937& rng, bool add_diagonal) {
  Data data(model);
  Eigen::MatrixXd a = crba(model, data, random_configuration(model, rng));
  if (add_diagonal) {
    a.diagonal() += 5.0 * (random_vector(model.nv, rng).array() + 1.0).matrix();
  }
  return a;
}

TEST_P(TreeFactorizationOnModels, SolvesAgreeWithDenseCholesky) {
  std::mt19937 rng(7);
  TreeFactorization tree(model_);
  for (int trial = 0; trial < 20; ++trial) {
    const Eigen::MatrixXd a = random_tree_matrix(model_, rng, trial % 2 == 1);
    ASSERT_TRUE(tree.compute(a));
    const Eigen::LLT<Eigen::MatrixXd> llt(a);
    ASSERT_EQ(llt.info(), Eigen::Success);
    Eigen::MatrixXd b(model_.nv, 3);
    for (int c = 0; c < 3; ++c) {
      b.col(c) = random_vector(model_.nv, rng);
    }
    // A^-1 b.
    Eigen::MatrixXd x = b;
    tree.solve_in_place(x);
    EXPECT_LT(relative_error(x, llt.solve(b)), 1e-12) << "trial " << trial;
    // The half solves: U^-T U^-1 = A^-1, and (U^-1 b)^T (U^-1 b) = b^T A^-1 b.
    Eigen::MatrixXd h = b;
    tree.half_solve_in_place(h);
    EXPECT_LT(relative_error(h.transpose() * h, b.transpose() * llt.solve(b)), 1e-12);
    tree.half_solve_transpose_in_place(h);
    EXPECT_LT(relative_error(h, llt.solve(b)), 1e-12);
    // A = L^T D L from the stored factor.
    const Eigen::MatrixXd& f = tree.factor();
    Eigen::MatrixXd l = Eigen::MatrixXd::Identity(model_.nv, model_.nv);
    for (int i = 0; i < model_.nv; ++i) {
      for (int j = tree.parent(i); j >= 0; j = tree.parent(j)) {
        l(i, j) = f(j, i);
      }
    }
    EXPECT_LT(relative_error(l.transpose() * f.diagonal().asDiagonal() * l, a), 1e-13);
  }
}

TEST_P(TreeFactorizationOnModels, BodyJacobianHalfSolveStaysOnItsAncestors) {
  std::mt19937 rng(3);
  Data data(model_);
  Eigen::MatrixXd a = crba(model_, data, random_configuration(model_, rng));
  TreeFactorization tree(model_);
  ASSERT_TRUE(tree.compute(a));
  const Eigen::LLT<Eigen::MatrixXd> llt(a);
  for (int body = 1; body < model_.n_bodies; ++body) {
    Eigen::Matrix<double, 6, Eigen::Dynamic> jacobian(6, model_.nv);
    body_origin_jacobian(model_, data, body, jacobian);
    Eigen::MatrixXd h = jacobian.transpose();
    tree.half_solve_in_place(h);
    // Zero outside the body's ancestor dofs, and H^T H = J A^-1 J^T.
    std::vector<bool> ancestor(model_.nv, false);
    for (int b = body; b > 0; b = model_.parent[b]) {
      for (int k = 0; k < model_.nv_joint[b]; ++k) {
        ancestor[model_.idx_v[b] + k] = true;
      }
    }
    for (int i = 0; i < model_.nv; ++i) {
      if (!ancestor[i]) {
        EXPECT_EQ(h.row(i).cwiseAbs().maxCoeff(), 0.0) << "body " << body << ", dof " << i;
      }
    }
    const Eigen::MatrixXd reference = jacobian * llt.solve(jacobian.transpose());
    EXPECT_LT(relative_error(h.transpose() * h, reference), 1e-12) << "body " << body;
  }
}

TEST_P(TreeFactorizationOnModels, RefusesAnIndefiniteMatrixAndDoesNotAllocate) {
  std::mt19937 rng(5);
  Eigen::MatrixXd a = random_tree_matrix(model_, rng, true);
  TreeFactorization tree(model_);
  Eigen::MatrixXd x = Eigen::MatrixXd::Ones(model_.nv, 6);
  Eigen::internal::set_is_malloc_allowed(false);
  const bool factored = tree.compute(a);
  tree.solve_in_place(x);
  tree.half_solve_in_place(x);
  tree.half_solve_transpose_in_place(x);
  Eigen::internal::set_is_malloc_allowed(true);
  EXPECT_TRUE(factored);
  a(0, 0) = -1.0;
  EXPECT_FALSE(tree.compute(a));
  a = random_tree_matrix(model_, rng, false);
  a(model_.nv - 1, model_.nv - 1) = 0.0; // a leaf's pivot, the first one
  EXPECT_FALSE(tree.compute(a));
}

INSTANTIATE_TEST_SUITE_P(
    Models, TreeFactorizationOnModels,
    ::testing::Values(std::make_tuple("hrp2/hrp2.urdf", true, false),
                      std::make_tuple("hrp2/hrp2.urdf", true, true),
                      std::make_tuple("test/branched_robot.urdf", true, false),
                      std::make_tuple("test/branched_robot.urdf", false, false),
                      std::make_tuple("test/double_pendulum.urdf", false, false)));

struct Trajectory {
  Eigen::MatrixXd q, v, impulses; // one column per step
  int max_contacts = 0;
};

/// @p n_steps steps of @p model under PD (kp 1e4, kd 200) towards its start, dropped from 2 mm
/// above the ground onto the contact points @p points (body, position), friction 0.8.
Trajectory simulate(const Model& model, const std::vector<std::pair<int, Eigen::Vector3d>>& points,
                    Eigen::VectorXd q, bool tree, int n_steps) {
  StepperParameters parameters;
  parameters.time_step = 1e-3;
  parameters.tree_factorization = tree;
  parameters.solver.solver = contact::ContactSolverType::automatic; // the scenes' default
  parameters.solver.tolerance = 1e-12;
  parameters.solver.max_iterations = 1000;
  Stepper stepper(model, parameters);
  stepper.set_gains(PdGains::Uniform(model, 1e4, 200.0));
  for (const auto& [body, position] : points) {
    stepper.add_contact_point(body, position, 0.8);
  }
  const Eigen::VectorXd q_ref = q, zero = Eigen::VectorXd::Zero(model.nv);
  Eigen::VectorXd v = zero;
  Trajectory out;
  out.q.resize(model.nq, n_steps);
  out.v.resize(model.nv, n_steps);
  out.impulses.resize(3 * points.size(), n_steps);
  for (int n = 0; n < n_steps; ++n) {
    out.max_contacts = std::max(out.max_contacts, stepper.step(q, v, zero, q_ref, zero).n_contacts);
    out.q.col(n) = q;
    out.v.col(n) = v;
    for (std::size_t k = 0; k < points.size(); ++k) {
      out.impulses.col(n).segment<3>(3 * k) = stepper.point_impulse(static_cast<int>(k));
    }
  }
  return out;
}

void expect_same_trajectories(const Trajectory& tree, const Trajectory& dense, const char* what) {
  const double e_q = relative_error(tree.q, dense.q), e_v = relative_error(tree.v, dense.v),
               e_p = relative_error(tree.impulses, dense.impulses);
  std::printf("%s: up to %d contacts; tree against dense factorization: relative differences "
              "q %.2e, v %.2e, impulses %.2e (tol 1e-9)\n",
              what, tree.max_contacts, e_q, e_v, e_p);
  EXPECT_GT(tree.max_contacts, 0);
  EXPECT_LT(e_q, 1e-9);
  EXPECT_LT(e_v, 1e-9);
  EXPECT_LT(e_p, 1e-9);
}

TEST(StepperWithTreeFactorization, Hrp2DropOnSixteenSolePointsAsWithDenseCholesky) {
  const Model model = load("hrp2/hrp2.urdf", true, false);
  Data data(model);
  Eigen::VectorXd q = model.neutral_configuration();
  forward_kinematics(model, data, q);
  std::vector<std::pair<int, Eigen::Vector3d>> points;
  double lowest = 1e9;
  for (const char* sole : {"r_sole", "l_sole"}) {
    const Frame& frame = model.frames[model.frame_id(sole)];
    for (double x : {-0.1, 0.0, 0.1}) {
      for (double y : {-0.06, 0.0, 0.06}) {
        if (x == 0.0 && y == 0.0) {
          continue; // the sole outline's 8 points
        }
        points.emplace_back(frame.body, frame.placement.act_point(Eigen::Vector3d(x, y, 0.0)));
        lowest = std::min(lowest, data.oMi[frame.body].act_point(points.back().second).z());
      }
    }
  }
  q[2] += 0.002 - lowest;
  const Trajectory tree = simulate(model, points, q, true, 300);
  const Trajectory dense = simulate(model, points, q, false, 300);
  expect_same_trajectories(tree, dense, "HRP-2 drop, 16 sole points");
}

TEST(StepperWithTreeFactorization, BranchedRobotTouchingWithEveryBodyAsWithDenseCholesky) {
  // 6 columns per contact body >= nv: the rows keep the full factor (no reduced factor).
  const Model model = load("test/branched_robot.urdf", true, false);
  Data data(model);
  std::mt19937 rng(11);
  Eigen::VectorXd q = random_configuration(model, rng);
  forward_kinematics(model, data, q);
  std::vector<std::pair<int, Eigen::Vector3d>> points;
  double lowest = 1e9;
  for (int body = 1; body < model.n_bodies; ++body) {
    points.emplace_back(body, Eigen::Vector3d(0.01, 0.02, -0.03));
    lowest = std::min(lowest, data.oMi[body].act_point(points.back().second).z());
  }
  ASSERT_GE(6 * (model.n_bodies - 1), model.nv);
  q[2] += 0.002 - lowest;
  const Trajectory tree = simulate(model, points, q, true, 200);
  const Trajectory dense = simulate(model, points, q, false, 200);
  expect_same_trajectories(tree, dense, "branched robot, one point per body");
}

} // namespace
} // namespace plantar::multibody
