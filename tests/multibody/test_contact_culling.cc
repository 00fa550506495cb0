// Contact culling of the stepper (multibody/stepper.h, StepperParameters::contact_margin):
// a foot high above the ground (a compliant patch and four rigid points fixed 1 m above a
// box landing on a compliant patch) gives no contact rows with the default margin 0, and the
// motion equals the one of the full problem (margin = infinity: every candidate in the
// contact problem, the high ones with zero impulse) to round-off. (It found that the
// activation test must use the unloaded gap of a patch node, g - U_prev: see stepper.cc.)

#include "coupling/pad_state.h"
#include "multibody/stepper.h"
#include "multibody/urdf_loader.h"
#include "tests/multibody/test_helpers.h"

#include <gtest/gtest.h>

#include <cstdio>
#include <limits>

namespace plantar::multibody {
namespace {

struct CullingRun {
  Eigen::VectorXd q, v;
  std::vector<int> n_contacts;
  std::vector<double> z;   // base height per step, m
  double high_impulse = 0; // max |p| on the high foot over the run, N s
  StepProfile profile;
};

CullingRun simulate(double margin) {
  const Model model = build_model_from_urdf(test::model_path("test/free_box.urdf"));
  StepperParameters parameters;
  parameters.time_step = 1e-3;
  parameters.contact_margin = margin;
  parameters.solver.solver = contact::ContactSolverType::gauss_seidel;
  parameters.solver.tolerance = 1e-12;
  Stepper stepper(model, parameters);
  Eigen::Matrix3Xd low(3, 4), high(3, 4);
  low << -0.2, 0.2, -0.2, 0.2, -0.1, -0.1, 0.1, 0.1, -0.05, -0.05, -0.05, -0.05;
  high = low;
  high.row(2).setConstant(1.0);
  Eigen::MatrixXd compliance = Eigen::MatrixXd::Identity(12, 12) * 5e-5;
  for (int k = 0; k < 4; ++k)
    compliance(3 * k + 2, 3 * k + 2) = 2e-5;
  compliance.block<3, 3>(0, 3) = compliance.block<3, 3>(3, 0) = Eigen::Matrix3d::Identity() * 1e-5;
  coupling::PadState low_pad(compliance), high_pad(compliance);
  stepper.add_deformable_patch(1, low, 0.8, low_pad);
  const int high_patch = stepper.add_deformable_patch(1, high, 0.8, high_pad);
  std::vector<int> high_points;
  for (int k = 0; k < 4; ++k)
    high_points.push_back(
        stepper.add_contact_point(1, high.col(k) + Eigen::Vector3d(0, 0, 0.1), 0.8));
  CullingRun r;
  r.q = model.neutral_configuration();
  r.v = Eigen::VectorXd::Zero(6);
  r.q[2] = 0.06; // 1 cm drop
  r.v[0] = 0.3;  // sliding in x
  r.v[4] = 0.5;  // and tipping
  const Eigen::VectorXd zero = Eigen::VectorXd::Zero(6);
  for (int n = 0; n < 400; ++n) {
    const StepReport report = stepper.step(r.q, r.v, zero, r.q, zero);
    r.n_contacts.push_back(report.n_contacts);
    r.z.push_back(r.q[2]);
    for (int k = 0; k < 4; ++k) {
      r.high_impulse = std::max(r.high_impulse, stepper.node_impulse(high_patch, k).norm());
      r.high_impulse = std::max(r.high_impulse, stepper.point_impulse(high_points[k]).norm());
    }
  }
  r.profile = stepper.profile();
  return r;
}

TEST(ContactCulling, HighFootHasNoRowsAndTheSameMotion) {
  const CullingRun culled = simulate(0.0);
  const CullingRun full = simulate(std::numeric_limits<double>::infinity());
  int max_culled = 0, min_full = 100, touching = 0;
  for (std::size_t n = 0; n < culled.n_contacts.size(); ++n) {
    max_culled = std::max(max_culled, culled.n_contacts[n]);
    min_full = std::min(min_full, full.n_contacts[n]);
    touching += culled.n_contacts[n] > 0;
  }
  int first_difference = -1;
  for (std::size_t n = 0; n < culled.z.size() && first_difference < 0; ++n)
    if (culled.z[n] != full.z[n])
      first_difference = static_cast<int>(n);
  double early = 0;
  for (std::size_t n = 0; n < 100; ++n)
    early = std::max(early, std::abs(culled.z[n] - full.z[n]));
  std::printf("first step with a different base height: %d (contacts culled %d); max |dz| over "
              "steps 0-99 %.2e m\n",
              first_difference, first_difference >= 0 ? culled.n_contacts[first_difference] : -1,
              early);
  const double dq = (culled.q - full.q).cwiseAbs().maxCoeff();
  const double dv = (culled.v - full.v).cwiseAbs().maxCoeff();
  std::printf("culled: at most %d contacts (%d of 400 steps touching), full: at least %d; "
              "|q - q_full| = %.2e, |v - v_full| = %.2e; max |p| on the high foot (full) %.2e N s; "
              "solve time culled %.3f ms, full %.3f ms\n",
              max_culled, touching, min_full, dq, dv, full.high_impulse,
              1e3 * culled.profile.contact_solve, 1e3 * full.profile.contact_solve);
  EXPECT_EQ(max_culled, 4);                // the landing patch only
  EXPECT_GT(touching, 300);                // it did land
  EXPECT_EQ(culled.n_contacts.front(), 0); // in the air: no rows at all
  EXPECT_EQ(min_full, 12);                 // every candidate: 4 + 4 patch nodes + 4 points
  EXPECT_EQ(culled.high_impulse, 0.0);
  EXPECT_EQ(full.high_impulse, 0.0);
  EXPECT_LT(dq, 1e-12);
  EXPECT_LT(dv, 1e-10);
  EXPECT_EQ(culled.profile.n_steps, 400);
  EXPECT_EQ(culled.profile.n_solves, touching);
}

TEST(ContactCulling, RejectsNegativeMargin) {
  StepperParameters parameters;
  parameters.contact_margin = -1e-3;
  EXPECT_THROW(parameters.validate(), std::invalid_argument);
}

} // namespace
} // namespace plantar::multibody
