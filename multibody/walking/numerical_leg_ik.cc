#include "multibody/walking/numerical_leg_ik.h"

#include "multibody/jacobian.h"
#include "multibody/kinematics.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <limits>
#include <stdexcept>
#include <string>

namespace plantar::walking {

using multibody::JointType;
using multibody::SE3;
using multibody::Vector6d;

namespace {

// Line search: Armijo's sufficient-decrease constant, and the smallest step fraction tried
// (halving from 1: 40 trials) before declaring that no decrease is possible.
constexpr double kArmijo = 1e-4;
constexpr double kMinStepFraction = 1e-12;
// Largest epsilon of the epsilon-active set (rad or m).
constexpr double kActiveMargin = 1e-3;
// A coordinate within this distance of a limit (rad or m) is reported "at the limit".
constexpr double kAtLimit = 1e-9;

/// printf-style formatting into a std::string (messages of exceptions only).
template <typename... Args> std::string format(const char* fmt, Args... args) {
  char buffer[256];
  std::snprintf(buffer, sizeof buffer, fmt, args...);
  return buffer;
}

/// Roll, pitch, yaw (rad) with R = Rz(yaw) Ry(pitch) Rx(roll).
Eigen::Vector3d rpy(const Eigen::Matrix3d& r) {
  // + 0.0 turns -0 into 0 for printing.
  return Eigen::Vector3d(std::atan2(r(2, 1), r(2, 2)) + 0.0,
                         std::atan2(-r(2, 0), std::hypot(r(2, 1), r(2, 2))) + 0.0,
                         std::atan2(r(1, 0), r(0, 0)) + 0.0);
}

} // namespace

NumericalLegIk::NumericalLegIk(const multibody::Model& model, std::vector<int> joints, int frame,
                               NumericalIkSettings settings)
    : model_(model), joints_(std::move(joints)), frame_(frame), settings_(settings), data_(model) {
  const std::string where = "NumericalLegIk: ";
  if (frame_ < 0 || frame_ >= static_cast<int>(model_.frames.size())) {
    throw std::invalid_argument(where + "frame index " + std::to_string(frame_) +
                                " out of range [0, " + std::to_string(model_.frames.size()) + ")");
  }
  const std::string& frame_name = model_.frames[frame_].name;
  if (joints_.empty()) {
    throw std::invalid_argument(where + "empty joint chain for frame '" + frame_name + "'");
  }
  const NumericalIkSettings& s = settings_;
  if (!(s.position_tolerance > 0.0) || !(s.rotation_tolerance > 0.0) || s.max_iterations < 1 ||
      !(s.damping >= 0.0) || !(s.min_damping > 0.0) || !(s.max_step > 0.0) ||
      !(s.step_tolerance > 0.0) || s.max_restarts < 0) {
    throw std::invalid_argument(where + "settings out of range (tolerances, min_damping, " +
                                "max_step, step_tolerance > 0, damping >= 0, max_iterations >= 1, "
                                "max_restarts >= 0)");
  }
  const int n = static_cast<int>(joints_.size());
  for (int k = 0; k < n; ++k) {
    const int j = joints_[k];
    if (j < 1 || j >= model_.n_bodies) {
      throw std::invalid_argument(where + "joint index " + std::to_string(j) +
                                  " out of range [1, " + std::to_string(model_.n_bodies) + ")");
    }
    const std::string& name = model_.joint_names[j];
    if ((model_.joint_type[j] != JointType::Revolute &&
         model_.joint_type[j] != JointType::Prismatic) ||
        model_.nq_joint[j] != 1 || model_.nv_joint[j] != 1) {
      throw std::invalid_argument(where + "joint '" + name +
                                  "' is not a 1-DoF revolute or prismatic joint");
    }
    if (std::count(joints_.begin(), joints_.end(), j) > 1) {
      throw std::invalid_argument(where + "joint '" + name + "' appears twice in the chain");
    }
    bool ancestor = false;
    for (int b = model_.frames[frame_].body; b > 0; b = model_.parent[b]) {
      ancestor = ancestor || b == j;
    }
    if (!ancestor) {
      throw std::invalid_argument(where + "joint '" + name + "' does not move frame '" +
                                  frame_name + "'");
    }
    idx_q_.push_back(model_.idx_q[j]);
    idx_v_.push_back(model_.idx_v[j]);
  }
  lower_.resize(n);
  upper_.resize(n);
  for (int k = 0; k < n; ++k) {
    lower_[k] = model_.lower_position_limit[idx_q_[k]];
    upper_[k] = model_.upper_position_limit[idx_q_[k]];
    restartable_ = restartable_ || std::isfinite(upper_[k] - lower_[k]);
  }
  q_work_.resize(model_.nq);
  q_trial_.resize(model_.nq);
  jacobian_.resize(6, n);
  hessian_.resize(n, n);
  x_.resize(n);
  best_x_.resize(n);
  gradient_.resize(n);
  rhs_.resize(n);
  step_.resize(n);
  active_.assign(n, 0);
  // Sizes the factorisation's storage (and sets its info(): a sized but never computed LLT's
  // info is uninitialised, and copying it is undefined behaviour, found by UBSan).
  llt_.compute(Eigen::MatrixXd::Identity(n, n));
}

void NumericalLegIk::compute_error(const SE3& target, Vector6d& error) const {
  const SE3 placement = multibody::frame_placement(model_, data_, frame_);
  error.head<3>() = placement.translation - target.translation;
  error.tail<3>() = multibody::log3(placement.rotation * target.rotation.transpose());
}

void NumericalLegIk::compute_jacobian(const Vector6d& error) {
  multibody::frame_jacobian(model_, data_, frame_, data_.jacobian);
  const Eigen::Matrix3d log_jacobian = multibody::log3_left_jacobian_inverse(error.tail<3>());
  for (int k = 0; k < static_cast<int>(idx_v_.size()); ++k) {
    const auto column = data_.jacobian.col(idx_v_[k]);
    jacobian_.col(k).head<3>() = column.head<3>();
    jacobian_.col(k).tail<3>().noalias() = log_jacobian * column.tail<3>();
  }
}

void NumericalLegIk::error_and_jacobian(const Eigen::Ref<const Eigen::VectorXd>& q,
                                        const SE3& target, Vector6d& error,
                                        Eigen::Ref<Eigen::MatrixXd> jacobian) {
  multibody::check_size(q.size(), model_.nq, "NumericalLegIk::error_and_jacobian: q");
  multibody::check_size(jacobian.rows(), 6, "NumericalLegIk::error_and_jacobian: rows");
  multibody::check_size(jacobian.cols(), jacobian_.cols(),
                        "NumericalLegIk::error_and_jacobian: cols");
  multibody::forward_kinematics(model_, data_, q);
  compute_error(target, error);
  compute_jacobian(error);
  jacobian = jacobian_;
}

bool NumericalLegIk::converged(const Vector6d& error) const {
  return error.head<3>().norm() <= settings_.position_tolerance &&
         error.tail<3>().norm() <= settings_.rotation_tolerance;
}

NumericalIkReport NumericalLegIk::solve(Eigen::Ref<Eigen::VectorXd> q, const SE3& target) {
  multibody::check_size(q.size(), model_.nq, "NumericalLegIk::solve: q");
  const int n = static_cast<int>(joints_.size());
  NumericalIkReport report;
  Vector6d error, best_error;
  double best_cost = std::numeric_limits<double>::infinity();
  Stop best_stop = Stop::max_iterations;
  int starts = 0;
  for (int start = 0; start <= (restartable_ ? settings_.max_restarts : 0); ++start) {
    ++starts;
    q_work_ = q;
    for (int k = 0; k < n; ++k) {
      const double range = upper_[k] - lower_[k];
      x_[k] = start == 0 || !std::isfinite(range)
                  ? std::clamp(q_work_[idx_q_[k]], lower_[k], upper_[k])
                  : lower_[k] + spread_fraction(start, k) * range;
      q_work_[idx_q_[k]] = x_[k];
    }
    const Stop stop = descend(target, error, report.iterations);
    if (stop == Stop::converged) {
      q = q_work_;
      report.restarts = start;
      report.position_error = error.head<3>().norm();
      report.rotation_error = error.tail<3>().norm();
      return report;
    }
    if (0.5 * error.squaredNorm() < best_cost) {
      best_cost = 0.5 * error.squaredNorm();
      best_error = error;
      best_stop = stop;
      best_x_ = x_;
    }
  }
  x_ = best_x_;
  fail(best_stop == Stop::max_iterations ? "no convergence within max_iterations"
       : best_stop == Stop::stationary   ? "stationary point of the error within the joint limits"
                                         : "line search found no decrease of the error",
       target, best_error, report.iterations, starts);
}

double NumericalLegIk::spread_fraction(int start, int k) {
  if (start == 1) {
    return 0.5;
  }
  // splitmix64 of (start, k): a deterministic uniform number in [0, 1).
  std::uint64_t z = 0x9E3779B97F4A7C15ULL * (static_cast<std::uint64_t>(start) * 1000003ULL +
                                             static_cast<std::uint64_t>(k) + 1ULL);
  z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ULL;
  z = (z ^ (z >> 27)) * 0x94D049BB133111EBULL;
  z ^= z >> 31;
  return static_cast<double>(z >> 11) * 0x1.0p-53;
}

NumericalLegIk::Stop NumericalLegIk::descend(const SE3& target, Vector6d& error, int& iterations) {
  const int n = static_cast<int>(joints_.size());
  Vector6d trial_error;
  multibody::forward_kinematics(model_, data_, q_work_);
  compute_error(target, error);
  double cost = 0.5 * error.squaredNorm();
  for (int iteration = 0; !converged(error); ++iteration) {
    if (iteration == settings_.max_iterations) {
      return Stop::max_iterations;
    }
    compute_jacobian(error);
    gradient_.noalias() = jacobian_.transpose() * error;
    const double lambda = settings_.damping * error.squaredNorm() + settings_.min_damping;

    // Active set (Bertsekas' epsilon-active set): coordinates within eps of a limit with the
    // gradient pointing out, eps = min(kActiveMargin, |x - P(x - g)|_inf); then, re-solving,
    // coordinates at a limit whose step points out. At most n passes, each adding at least one.
    double eps = 0.0;
    for (int k = 0; k < n; ++k) {
      eps = std::max(eps, std::abs(x_[k] - std::clamp(x_[k] - gradient_[k], lower_[k], upper_[k])));
    }
    eps = std::min(eps, kActiveMargin);
    for (int k = 0; k < n; ++k) {
      active_[k] = (x_[k] <= lower_[k] + eps && gradient_[k] > 0.0) ||
                   (x_[k] >= upper_[k] - eps && gradient_[k] < 0.0);
    }
    for (int pass = 0; pass <= n; ++pass) {
      hessian_.noalias() = jacobian_.transpose() * jacobian_;
      hessian_.diagonal().array() += lambda;
      rhs_ = -gradient_;
      for (int k = 0; k < n; ++k) {
        if (active_[k]) {
          // Scaled gradient step for an active coordinate (onto its limit by the projection).
          rhs_[k] *= 1.0 / hessian_(k, k);
          hessian_.row(k).setZero();
          hessian_.col(k).setZero();
          hessian_(k, k) = 1.0;
        }
      }
      llt_.compute(hessian_);
      step_ = llt_.solve(rhs_);
      bool added = false;
      for (int k = 0; k < n; ++k) {
        if (!active_[k] &&
            ((x_[k] <= lower_[k] && step_[k] < 0.0) || (x_[k] >= upper_[k] && step_[k] > 0.0))) {
          active_[k] = 1;
          added = true;
        }
      }
      if (!added) {
        break;
      }
    }
    const double largest = step_.cwiseAbs().maxCoeff();
    if (largest > settings_.max_step) {
      step_ *= settings_.max_step / largest;
    }
    double moved = 0.0; // largest coordinate change of the projected full step
    for (int k = 0; k < n; ++k) {
      moved = std::max(moved, std::abs(std::clamp(x_[k] + step_[k], lower_[k], upper_[k]) - x_[k]));
    }
    if (moved <= settings_.step_tolerance) {
      return Stop::stationary;
    }

    // Backtracking line search along the projection arc x(alpha) = P(x + alpha d), Armijo's
    // rule with the first-order change g^T (x(alpha) - x) (Bertsekas 1982).
    q_trial_ = q_work_;
    double alpha = 1.0;
    double trial_cost = cost;
    for (;;) {
      double predicted = 0.0;
      for (int k = 0; k < n; ++k) {
        const double xk = std::clamp(x_[k] + alpha * step_[k], lower_[k], upper_[k]);
        predicted += gradient_[k] * (xk - x_[k]);
        q_trial_[idx_q_[k]] = xk;
      }
      multibody::forward_kinematics(model_, data_, q_trial_);
      compute_error(target, trial_error);
      trial_cost = 0.5 * trial_error.squaredNorm();
      if ((trial_cost < cost && trial_cost <= cost + kArmijo * predicted) ||
          converged(trial_error)) {
        break;
      }
      alpha *= 0.5;
      if (alpha < kMinStepFraction) {
        return Stop::line_search;
      }
    }
    ++iterations;
    q_work_.swap(q_trial_);
    for (int k = 0; k < n; ++k) {
      x_[k] = q_work_[idx_q_[k]];
    }
    error = trial_error;
    cost = trial_cost;
  }
  return Stop::converged;
}

void NumericalLegIk::fail(const char* reason, const SE3& target, const Vector6d& error,
                          int iterations, int starts) const {
  const Eigen::Vector3d angles = rpy(target.rotation);
  std::string message =
      "NumericalLegIk: frame '" + model_.frames[frame_].name + "' not reached (" + reason +
      format(", %d iterations from %d starts): target position (%.6g, %.6g, %.6g) m, "
             "rpy (%.6g, %.6g, %.6g) rad",
             iterations, starts, target.translation.x(), target.translation.y(),
             target.translation.z(), angles.x(), angles.y(), angles.z()) +
      format("; residual position error %.3e m, rotation error %.3e rad; joints at a limit:",
             error.head<3>().norm(), error.tail<3>().norm());
  bool any = false;
  for (int k = 0; k < static_cast<int>(joints_.size()); ++k) {
    const bool at_lower = x_[k] <= lower_[k] + kAtLimit;
    const bool at_upper = x_[k] >= upper_[k] - kAtLimit;
    if (at_lower || at_upper) {
      message += " " + model_.joint_names[joints_[k]] +
                 format(" (%s limit %.6g, value %.6g)", at_lower ? "lower" : "upper",
                        at_lower ? lower_[k] : upper_[k], x_[k]);
      any = true;
    }
  }
  if (!any) {
    message += " none";
  }
  throw std::runtime_error(message);
}

} // namespace plantar::walking
