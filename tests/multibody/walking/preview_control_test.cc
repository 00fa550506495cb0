// Cart-table ZMP preview control: gains from the Riccati equation against
// jrl-walkgen's published HRP-2 gains, and tracking of a ZMP step.
#include "multibody/walking/preview_control.h"

#include <cmath>
#include <cstdio>
#include <gtest/gtest.h>
#include <stdexcept>

namespace {

using namespace plantar::walking;

TEST(PreviewControl, GainsMatchJrlWalkgen) {
  const PreviewControlParameters params; // T = 5 ms, z_c = 0.814 m, 1.6 s, Q = 1, R = 1e-6
  const PreviewGains gains = compute_preview_gains(params);
  // DARE residual relative to |P|: the iteration's answer solves the equation.
  const double residual = riccati_residual(params, gains.riccati);
  const double p_scale = gains.riccati.cwiseAbs().maxCoeff();
  std::printf("Riccati: %d iterations, max|P| = %.6g, residual %.3g (relative %.3g, tol 1e-9)\n",
              gains.n_riccati_iterations, p_scale, residual, residual / p_scale);
  EXPECT_LT(residual / p_scale, 1e-9);
  // jrl-walkgen src/data/PreviewControlParameters.ini (via hrp2.md): Kx = [72719, 21550, 177.01],
  // Ks = 618.7, preview gains 618.7, 777.51, ... (printed as -G_d). Relative tolerance: the
  // published digits (5e-4 for 5 significant digits).
  const double published_kx[3] = {72719.0, 21550.0, 177.01};
  std::printf("G_i = %.6g (published Ks 618.7)\n", gains.integral_gain);
  EXPECT_NEAR(gains.integral_gain / 618.7, 1.0, 5e-4);
  for (int i = 0; i < 3; ++i) {
    std::printf("G_x[%d] = %.6g (published %.6g, relative difference %.2e)\n", i,
                gains.state_gain(i), published_kx[i], gains.state_gain(i) / published_kx[i] - 1);
    EXPECT_NEAR(gains.state_gain(i) / published_kx[i], 1.0, 5e-4);
  }
  std::printf("-G_d(1), -G_d(2) = %.6g, %.6g (published 618.7, 777.51)\n", -gains.preview_gains(0),
              -gains.preview_gains(1));
  EXPECT_NEAR(-gains.preview_gains(0) / 618.7, 1.0, 5e-4);
  EXPECT_NEAR(-gains.preview_gains(1) / 777.51, 1.0, 5e-4);
  // Shape: negative, |G_d| rises to a peak within the first 0.1 s, then decays to under 1% of
  // the peak by the end of the 1.6 s horizon (why 1.6 s previews well and 0.8 s does not).
  const Eigen::VectorXd& gd = gains.preview_gains;
  ASSERT_EQ(gd.size(), 320);
  Eigen::Index peak_index;
  const double peak = gd.cwiseAbs().maxCoeff(&peak_index);
  const double at_08 = std::abs(gd(159)), at_end = std::abs(gd(gd.size() - 1));
  std::printf("|G_d| peak %.6g at %.3f s; |G_d(0.8 s)|/peak = %.4f; |G_d(1.6 s)|/peak = %.5f\n",
              peak, (peak_index + 1) * params.period, at_08 / peak, at_end / peak);
  EXPECT_LT(gd.maxCoeff(), 0.0);
  EXPECT_GT(peak_index, 0);
  EXPECT_LT((peak_index + 1) * params.period, 0.1);
  EXPECT_GT(at_08 / peak, 0.01);
  EXPECT_LT(at_end / peak, 0.01);
  // Monotone decay after the peak.
  for (Eigen::Index j = peak_index + 1; j < gd.size(); ++j)
    ASSERT_LE(std::abs(gd(j)), std::abs(gd(j - 1)) * (1 + 1e-12)) << j;
}

TEST(PreviewControl, TracksZmpStep) {
  const PreviewControlParameters params;
  const PreviewGains gains = compute_preview_gains(params);
  // ZMP reference: 0 for 2 s (longer than the 1.6 s preview, so the start is at rest), then a
  // 0.1 m step, held 5 s.
  const int n = 1400, n_step = 400;
  const double step = 0.1;
  Eigen::VectorXd reference = Eigen::VectorXd::Zero(n);
  reference.tail(n - n_step).setConstant(step);
  Eigen::MatrixX3d states;
  Eigen::VectorXd zmp;
  run_preview_control(params, gains, reference, Eigen::Vector3d::Zero(), states, zmp);
  // Independent check of the cart-table output: p = x - z_c/g x'' recomputed from the states.
  double zmp_formula_error = 0.0;
  for (int k = 0; k < n; ++k)
    zmp_formula_error = std::max(
        zmp_formula_error,
        std::abs(zmp(k) - (states(k, 0) - params.com_height / params.gravity * states(k, 2))));
  // And the states integrate exactly (constant jerk between samples): x(k+1) from a Taylor step.
  double integration_error = 0.0;
  const double T = params.period;
  for (int k = 0; k + 1 < n; ++k) {
    const double jerk = (states(k + 1, 2) - states(k, 2)) / T;
    const double x_next =
        states(k, 0) + T * states(k, 1) + T * T / 2 * states(k, 2) + T * T * T / 6 * jerk;
    integration_error = std::max(integration_error, std::abs(x_next - states(k + 1, 0)));
  }
  const double steady_zmp_error = std::abs(zmp(n - 1) - step);
  const double steady_com_error = std::abs(states(n - 1, 0) - step);
  double max_tracking_error = 0.0;
  for (int k = 0; k < n; ++k)
    max_tracking_error = std::max(max_tracking_error, std::abs(zmp(k) - reference(k)));
  // CoM starts moving before the step (preview): at 0.5 s before the step it has moved.
  const double com_before = states(n_step - 1, 0);
  std::printf("step 0.1 m at 2 s: steady ZMP error %.3e m, steady CoM error %.3e m (tol 1e-3); "
              "max |p - p_ref| %.4f m; CoM at step time %.4f m (anticipation); "
              "ZMP formula check %.2e, integration check %.2e\n",
              steady_zmp_error, steady_com_error, max_tracking_error, com_before, zmp_formula_error,
              integration_error);
  EXPECT_LT(steady_zmp_error, 1e-3);
  EXPECT_LT(steady_com_error, 1e-3);
  EXPECT_LT(zmp_formula_error, 1e-12);
  EXPECT_LT(integration_error, 1e-12);
  // Anticipation: the CoM is already half-way-ish towards the new ZMP when the step occurs
  // (for an ideal preview on a symmetric step, x(t_step) ~ step / 2).
  EXPECT_GT(com_before, 0.3 * step);
  EXPECT_LT(com_before, 0.7 * step);
  // Kajita 2003 Fig. 6: the ZMP follows the reference with small under- and overshoots only
  // (the cart-table ZMP is continuous, so |p - p_ref| ~ step at the step instant itself).
  const double undershoot = -zmp.head(n_step).minCoeff(), overshoot = zmp.maxCoeff() - step;
  std::printf("undershoot before the step %.4f m, overshoot after %.4f m (tol 0.1 step each)\n",
              undershoot, overshoot);
  EXPECT_LT(undershoot, 0.1 * step);
  EXPECT_LT(overshoot, 0.1 * step);
}

TEST(PreviewControl, RejectsBadParameters) {
  PreviewControlParameters params;
  params.com_height = -0.8;
  EXPECT_THROW(compute_preview_gains(params), std::invalid_argument);
  params = PreviewControlParameters();
  params.period = 0.0;
  EXPECT_THROW(compute_preview_gains(params), std::invalid_argument);
  params = PreviewControlParameters();
  params.max_riccati_iterations = 3;
  EXPECT_THROW(compute_preview_gains(params), std::runtime_error);
}

} // namespace
