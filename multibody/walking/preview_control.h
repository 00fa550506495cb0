// ZMP preview control on the cart-table model (Kajita et al., ICRA 2003).
#pragma once

#include <Eigen/Core>
#include <vector>

namespace plantar::walking {

/// Parameters of the cart-table preview controller. One horizontal axis; the
/// same gains serve x and y.
struct PreviewControlParameters {
  double period = 0.005; ///< T, control period [s], (0, 0.1]. Kajita 2003: 5 ms.
  double com_height =
      0.814;             ///< z_c, CoM height of the cart [m], (0, 10]. jrl-walkgen HRP-2: 0.814.
  double gravity = 9.81; ///< g [m/s^2], > 0.
  double preview_time = 1.6;  ///< preview horizon [s], >= period. Kajita 2003: 1.6 s.
  double weight_error = 1.0;  ///< Q_e, weight on the ZMP error e = p - p_ref, > 0.
  double weight_state = 0.0;  ///< Q_x, weight on the state increment (all three entries), >= 0.
  double weight_input = 1e-6; ///< R, weight on the jerk increment du^2, > 0.
  int max_riccati_iterations = 200000; ///< fixed-point iterations of the DARE, > 0.
  double riccati_tolerance = 1e-13;    ///< relative change of P that stops the iteration, > 0.
};

/// Cart-table model: state s = (x, x', x'') [m, m/s, m/s^2], input u = x''' [m/s^3],
///   s(k+1) = A s(k) + B u(k),  p(k) = C s(k)   (ZMP, Kajita 2003 eq. 6-7)
/// A = [[1, T, T^2/2], [0, 1, T], [0, 0, 1]], B = [T^3/6, T^2/2, T]^T, C = [1, 0, -z_c/g].
struct CartTable {
  Eigen::Matrix3d A;
  Eigen::Vector3d B;
  Eigen::RowVector3d C;
};

/// Builds the cart-table matrices. @throws std::invalid_argument on a parameter out of range.
CartTable make_cart_table(const PreviewControlParameters& params);

/// Gains of the optimal preview servo (Katayama et al. 1985, as in Kajita 2003 eq. 8-12):
///   u(k) = -integral_gain * sum_{i<=k} (p(i) - p_ref(i)) - state_gain * s(k)
///          - sum_{j=1..n_preview} preview_gains(j-1) * p_ref(k+j).
/// They come from the discrete algebraic Riccati equation (DARE) of the augmented
/// error system  xa(k+1) = Aa xa(k) + Ba du(k), xa = (e(k), s(k) - s(k-1)),
///   Aa = [[1, C A], [0, A]], Ba = [C B; B], cost sum Q_e e^2 + dx' Q_x dx + R du^2.
/// Sign convention: Kajita's (preview_gains(0) = -integral_gain < 0). jrl-walkgen
/// prints -preview_gains (see docs/walking.md).
struct PreviewGains {
  double integral_gain = 0.0;    ///< G_i [1/s^3] (jerk per metre of summed ZMP error)
  Eigen::RowVector3d state_gain; ///< G_x [1/s^3, 1/s^2, 1/s]
  Eigen::VectorXd preview_gains; ///< G_d(1..n_preview) [1/s^3], n_preview = round(preview_time / T)
  Eigen::Matrix4d riccati;       ///< P, the DARE solution (4x4)
  int n_riccati_iterations = 0;  ///< iterations used to converge
};

/// Solves the DARE by fixed-point iteration and computes the gains.
/// @throws std::runtime_error if the iteration does not converge or produces NaN.
PreviewGains compute_preview_gains(const PreviewControlParameters& params);

/// Residual norm of the DARE for P: || Q + Aa'P Aa - Aa'P Ba (R + Ba'P Ba)^-1 Ba'P Aa - P ||_max,
/// used by the tests to check the solution independently of the iteration.
double riccati_residual(const PreviewControlParameters& params, const Eigen::Matrix4d& P);

/// Runs the preview servo on the cart-table along a whole ZMP reference.
/// @param zmp_reference  p_ref(k), k = 0..n-1 [m], sampled at params.period; beyond the
///                       end the last value is held (the preview needs n_preview samples ahead).
/// @param initial_state  s(0) = (x, x', x'').
/// @param[out] states    n x 3: s(k) for k = 0..n-1 (CoM position, velocity, acceleration).
/// @param[out] zmp       n: p(k) = C s(k), the cart-table ZMP of the CoM trajectory.
void run_preview_control(const PreviewControlParameters& params, const PreviewGains& gains,
                         const Eigen::VectorXd& zmp_reference, const Eigen::Vector3d& initial_state,
                         Eigen::MatrixX3d& states, Eigen::VectorXd& zmp);

} // namespace plantar::walking
