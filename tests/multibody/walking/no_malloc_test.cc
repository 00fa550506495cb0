// Per-time-step functions of plantar_walking allocate nothing: the library sources are compiled
// into this test with EIGEN_RUNTIME_NO_MALLOC (eigen_no_malloc_config.h), and heap allocations
// are counted as well (tests/allocation_counter.h; this covers plantar_multibody, a library).
#include "multibody/kinematics.h"
#include "multibody/walking/joint_reference.h"
#include "multibody/walking/leg_ik.h"
#include "multibody/walking/numerical_leg_ik.h"
#include "tests/multibody/walking/hrp2_humanoid.h"

#include "tests/allocation_counter.h"

#include <cstdio>
#include <gtest/gtest.h>

namespace {

using namespace plantar::walking;

using plantar::walking::testing::hrp2_description;
using plantar::walking::testing::hrp2_model;

TEST(NoMalloc, GuardIsActive) {
  // The guard must fire on a dynamic allocation, otherwise the other tests prove nothing.
  Eigen::internal::set_is_malloc_allowed(false);
  bool fired = false;
  try {
    Eigen::VectorXd v(100);
    v.setZero();
  } catch (const std::runtime_error&) {
    fired = true;
  }
  Eigen::internal::set_is_malloc_allowed(true);
  EXPECT_TRUE(fired);
}

TEST(NoMalloc, LegIkSampleAndNumericalIk) {
  const plantar::multibody::Model model = hrp2_model();
  const Humanoid humanoid(model, hrp2_description());
  const LegGeometry leg = read_leg_geometry(model, humanoid, LegSide::left);
  const int n = humanoid.n_joints();
  JointReference ref;
  ref.resize(3, 0.005, humanoid.joint_names);
  const Eigen::VectorXd q = Eigen::VectorXd::Constant(n, 0.1);
  Eigen::Isometry3d base = Eigen::Isometry3d::Identity();
  for (int k = 0; k < 3; ++k)
    ref.set(k, base, (k + 1) * q, Eigen::Vector3d::Zero());
  LegAngles leg_q;
  leg_q << 0.1, 0.05, -0.4, 0.8, -0.4, -0.05;
  base.translation() = Eigen::Vector3d(0.1, 0.0, 0.65);
  Eigen::Isometry3d sole, sampled_base;
  LegAngles solved;
  Eigen::VectorXd sampled(n);

  // Numerical IK of the right leg: target from the model's FK at known angles, warm start
  // 0.05 rad away (as from the previous sample of a walk).
  const std::vector<int> right_joints(humanoid.leg_joints[0].begin(), humanoid.leg_joints[0].end());
  const int right_sole = humanoid.sole_frames[0];
  NumericalLegIk numerical(model, right_joints, right_sole);
  LegAngles right_q;
  right_q << -0.1, -0.05, -0.45, 0.9, -0.45, 0.05;
  Eigen::VectorXd q_full = model.neutral_configuration();
  q_full.head<3>() = base.translation();
  for (int i = 0; i < 6; ++i)
    q_full[model.idx_q[right_joints[i]]] = right_q[i];
  plantar::multibody::Data data(model);
  plantar::multibody::forward_kinematics(model, data, q_full);
  const plantar::multibody::SE3 target =
      plantar::multibody::frame_placement(model, data, right_sole);
  for (int i = 0; i < 6; ++i)
    q_full[model.idx_q[right_joints[i]]] = right_q[i] + (i % 2 ? -0.05 : 0.05);
  NumericalIkReport report;

  const long news_before = plantar::testing::n_allocations.load();
  plantar::testing::counting = true;
  Eigen::internal::set_is_malloc_allowed(false);
  sole = leg_forward_kinematics(leg, base, leg_q);
  solve_leg_ik(leg, base, sole, solved);
  ref.sample(0.0075, sampled, sampled_base);
  report = numerical.solve(q_full, target);
  Eigen::internal::set_is_malloc_allowed(true);
  plantar::testing::counting = false;
  const long news = plantar::testing::n_allocations.load() - news_before;

  // The results are right too (against the closed form's inputs, the numerical target by the
  // model's FK, and the interpolation of a linear reference).
  LegAngles right_solved;
  for (int i = 0; i < 6; ++i)
    right_solved[i] = q_full[model.idx_q[right_joints[i]]];
  plantar::multibody::forward_kinematics(model, data, q_full);
  const plantar::multibody::SE3 reached =
      plantar::multibody::frame_placement(model, data, right_sole);
  const double numerical_error =
      (reached.translation - target.translation).norm() +
      Eigen::AngleAxisd(reached.rotation.transpose() * target.rotation).angle();
  std::printf("operator new calls: %ld; IK error %.2e rad; sample error %.2e; numerical IK: %d "
              "iterations, sole error %.2e (m + rad), angle error %.2e rad\n",
              news, (solved - leg_q).cwiseAbs().maxCoeff(),
              (sampled - 2.5 * q).cwiseAbs().maxCoeff(), report.iterations, numerical_error,
              (right_solved - right_q).cwiseAbs().maxCoeff());
  EXPECT_EQ(news, 0);
  EXPECT_LT((solved - leg_q).cwiseAbs().maxCoeff(), 1e-12);
  EXPECT_LT((sampled - 2.5 * q).cwiseAbs().maxCoeff(), 1e-12);
  EXPECT_GT(report.iterations, 0);
  EXPECT_LT(numerical_error, 1e-9);
  EXPECT_LT((right_solved - right_q).cwiseAbs().maxCoeff(), 1e-8);
}

} // namespace
