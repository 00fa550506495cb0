#include "multibody/walking/preview_control.h"

#include <Eigen/LU>
#include <algorithm>
#include <cmath>
#include <sstream>
#include <stdexcept>

namespace plantar::walking {
namespace {

void check_range(const char* name, double value, double lower, double upper, bool lower_open) {
  const bool ok = (lower_open ? value > lower : value >= lower) && value <= upper;
  if (!ok || !std::isfinite(value)) {
    std::ostringstream msg;
    msg << "PreviewControlParameters." << name << " = " << value << " is outside "
        << (lower_open ? "(" : "[") << lower << ", " << upper << "]";
    throw std::invalid_argument(msg.str());
  }
}

void check(const PreviewControlParameters& p) {
  check_range("period", p.period, 0.0, 0.1, true);
  check_range("com_height", p.com_height, 0.0, 10.0, true);
  check_range("gravity", p.gravity, 0.0, 100.0, true);
  check_range("preview_time", p.preview_time, p.period, 100.0, false);
  check_range("weight_error", p.weight_error, 0.0, 1e12, true);
  check_range("weight_state", p.weight_state, 0.0, 1e12, false);
  check_range("weight_input", p.weight_input, 0.0, 1e12, true);
  check_range("riccati_tolerance", p.riccati_tolerance, 0.0, 1.0, true);
  if (p.max_riccati_iterations <= 0)
    throw std::invalid_argument("PreviewControlParameters.max_riccati_iterations = " +
                                std::to_string(p.max_riccati_iterations) + " must be > 0");
}

struct Augmented {
  Eigen::Matrix4d A;
  Eigen::Vector4d B;
  Eigen::Matrix4d Q;
  double R;
};

Augmented make_augmented(const PreviewControlParameters& params) {
  const CartTable ct = make_cart_table(params);
  Augmented aug;
  aug.A.setZero();
  aug.A(0, 0) = 1.0;
  aug.A.block<1, 3>(0, 1) = ct.C * ct.A;
  aug.A.block<3, 3>(1, 1) = ct.A;
  aug.B(0) = ct.C * ct.B;
  aug.B.tail<3>() = ct.B;
  aug.Q.setZero();
  aug.Q(0, 0) = params.weight_error;
  aug.Q.block<3, 3>(1, 1) = params.weight_state * Eigen::Matrix3d::Identity();
  aug.R = params.weight_input;
  return aug;
}

} // namespace

CartTable make_cart_table(const PreviewControlParameters& params) {
  check(params);
  const double T = params.period;
  CartTable ct;
  ct.A << 1.0, T, T * T / 2.0, 0.0, 1.0, T, 0.0, 0.0, 1.0;
  ct.B << T * T * T / 6.0, T * T / 2.0, T;
  ct.C << 1.0, 0.0, -params.com_height / params.gravity;
  return ct;
}

double riccati_residual(const PreviewControlParameters& params, const Eigen::Matrix4d& P) {
  const Augmented a = make_augmented(params);
  const double s = a.R + a.B.dot(P * a.B);
  const Eigen::RowVector4d BtPA = a.B.transpose() * P * a.A;
  const Eigen::Matrix4d rhs = a.Q + a.A.transpose() * P * a.A - BtPA.transpose() * BtPA / s;
  return (rhs - P).cwiseAbs().maxCoeff();
}

PreviewGains compute_preview_gains(const PreviewControlParameters& params) {
  const Augmented a = make_augmented(params);
  // Fixed-point iteration of P = Q + A'PA - A'PB (R + B'PB)^-1 B'PA from P = Q.
  Eigen::Matrix4d P = a.Q;
  int iteration = 0;
  double change = 1.0;
  for (; iteration < params.max_riccati_iterations; ++iteration) {
    const double s = a.R + a.B.dot(P * a.B);
    const Eigen::RowVector4d BtPA = a.B.transpose() * P * a.A;
    Eigen::Matrix4d next = a.Q + a.A.transpose() * P * a.A - BtPA.transpose() * BtPA / s;
    next = 0.5 * (next + next.transpose()).eval();
    change = (next - P).cwiseAbs().maxCoeff() / next.cwiseAbs().maxCoeff();
    P = next;
    if (!P.allFinite())
      throw std::runtime_error("compute_preview_gains: Riccati iteration produced NaN/Inf at "
                               "iteration " +
                               std::to_string(iteration));
    if (change < params.riccati_tolerance)
      break;
  }
  if (change >= params.riccati_tolerance) {
    std::ostringstream msg;
    msg << "compute_preview_gains: Riccati iteration did not converge in "
        << params.max_riccati_iterations << " iterations (relative change " << change
        << ", tolerance " << params.riccati_tolerance << ")";
    throw std::runtime_error(msg.str());
  }
  PreviewGains gains;
  gains.riccati = P;
  gains.n_riccati_iterations = iteration + 1;
  const double s = a.R + a.B.dot(P * a.B);
  const Eigen::RowVector4d K = a.B.transpose() * P * a.A / s; // [G_i, G_x]
  gains.integral_gain = K(0);
  gains.state_gain = K.tail<3>();
  // Preview gains: Ac = Aa - Ba K; X(1) = -Ac' P I1; G_d(1) = -G_i;
  // G_d(j) = (R + B'PB)^-1 B' X(j-1); X(j) = Ac' X(j-1).
  const int n_preview = static_cast<int>(std::lround(params.preview_time / params.period));
  gains.preview_gains.resize(n_preview);
  const Eigen::Matrix4d Ac = a.A - a.B * K;
  Eigen::Vector4d X = -Ac.transpose() * P * Eigen::Vector4d::UnitX();
  gains.preview_gains(0) = -gains.integral_gain;
  for (int j = 1; j < n_preview; ++j) {
    gains.preview_gains(j) = a.B.dot(X) / s;
    X = Ac.transpose() * X;
  }
  if (!gains.preview_gains.allFinite() || !gains.state_gain.allFinite())
    throw std::runtime_error("compute_preview_gains: gains are not finite");
  return gains;
}

void run_preview_control(const PreviewControlParameters& params, const PreviewGains& gains,
                         const Eigen::VectorXd& zmp_reference, const Eigen::Vector3d& initial_state,
                         Eigen::MatrixX3d& states, Eigen::VectorXd& zmp) {
  const CartTable ct = make_cart_table(params);
  const Eigen::Index n = zmp_reference.size();
  if (n == 0)
    throw std::invalid_argument("run_preview_control: empty ZMP reference");
  const Eigen::Index n_preview = gains.preview_gains.size();
  states.resize(n, 3);
  zmp.resize(n);
  Eigen::Vector3d s = initial_state;
  double error_sum = 0.0;
  for (Eigen::Index k = 0; k < n; ++k) {
    states.row(k) = s.transpose();
    zmp(k) = ct.C * s;
    error_sum += zmp(k) - zmp_reference(k);
    double preview = 0.0;
    for (Eigen::Index j = 1; j <= n_preview; ++j)
      preview += gains.preview_gains(j - 1) * zmp_reference(std::min(k + j, n - 1));
    const double u = -gains.integral_gain * error_sum - gains.state_gain * s - preview;
    s = ct.A * s + ct.B * u;
  }
  if (!states.allFinite())
    throw std::runtime_error("run_preview_control: CoM trajectory is not finite");
}

} // namespace plantar::walking
