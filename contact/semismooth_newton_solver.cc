#include "contact/semismooth_newton_solver.h"

#include "contact/coulomb_cone.h"
#include "contact/dense_lu.h"
#include "contact/sparse_newton_system.h"
#include "contact/woodbury_newton_system.h"

#include <algorithm>
#include <cmath>
#include <sstream>
#include <stdexcept>

namespace plantar::contact {

namespace {
constexpr int kMeritMemory = 5;     // non-monotone line search: reference over these
constexpr double kArmijo = 1e-4;    // sufficient decrease
constexpr double kMinStep = 1e-10;  // smallest step length tried
constexpr double kShortStep = 1e-4; // an accepted step shorter than this raises delta
constexpr double kDeltaMin = 1e-12; // regularisation of J, bounds (J is dimensionless)
constexpr double kDeltaMax = 1e-2;
constexpr int kVelocityRefresh = 20;        // u recomputed from r every this many iterations
constexpr double kLevenbergMarquardt = 1.0; // the regularisation floor's factor
constexpr int kFloorAfter = 10;             // iterations after which the floor is engaged anyway
} // namespace

void SemismoothNewtonSolver::resize(int max_contacts, int rigid_rank) {
  const int n3 = 3 * max_contacts;
  woodbury_.resize(max_contacts, rigid_rank);
  apply_work_.setZero(std::max(n3, rigid_rank));
  delassus_.setZero(n3, n3);
  jacobian_.setZero(n3, n3);
  pivots_.setZero(n3);
  active_.setZero(max_contacts);
  separated_.setZero(max_contacts);
  a_blocks_.setZero(3, n3);
  b_blocks_.setZero(3, n3);
  for (Eigen::VectorXd* v :
       {&rho_, &r_, &u_, &phi_, &step_, &w_step_, &rhs_, &trial_r_, &trial_u_, &trial_phi_})
    v->setZero(n3);
  merits_.setZero(kMeritMemory);
}

bool SemismoothNewtonSolver::contact_function(const Eigen::Vector3d& r, const Eigen::Vector3d& u,
                                              double mu, double rho, Eigen::Vector3d& phi,
                                              Eigen::Matrix3d* dphi_dr, Eigen::Matrix3d* dphi_du) {
  const double a = r[0] - rho * u[0];
  if (a <= 0.0) { // separated: Phi = r (the disk has radius 0)
    phi = r;
    if (dphi_dr != nullptr) {
      dphi_dr->setIdentity();
      dphi_du->setZero();
    }
    return true;
  }
  phi[0] = rho * u[0];
  const double w1 = r[1] - rho * u[1], w2 = r[2] - rho * u[2];
  const double radius = mu * a;
  const double norm_w = std::sqrt(w1 * w1 + w2 * w2);
  if (dphi_dr != nullptr) {
    dphi_dr->setZero();
    dphi_du->setZero();
    (*dphi_du)(0, 0) = rho;
  }
  if (norm_w <= radius) { // sticking: Phi_t = rho u_t
    phi[1] = rho * u[1];
    phi[2] = rho * u[2];
    if (dphi_dr != nullptr) {
      (*dphi_du)(1, 1) = rho;
      (*dphi_du)(2, 2) = rho;
    }
    return false;
  }
  // Sliding: Phi_t = r_t - R n, n = w / ||w||.
  const double n1 = w1 / norm_w, n2 = w2 / norm_w;
  phi[1] = r[1] - radius * n1;
  phi[2] = r[2] - radius * n2;
  if (dphi_dr != nullptr) {
    // Q = dP/dw = (R / ||w||) (I - n n^T); dPhi_t/dr_t = I - Q, dPhi_t/du_t = rho Q;
    // dPhi_t/dr_n = -mu n, dPhi_t/du_n = mu rho n.
    const double s = radius / norm_w;
    const double q11 = s * (1.0 - n1 * n1), q12 = -s * n1 * n2, q22 = s * (1.0 - n2 * n2);
    (*dphi_dr)(1, 1) = 1.0 - q11;
    (*dphi_dr)(1, 2) = -q12;
    (*dphi_dr)(2, 1) = -q12;
    (*dphi_dr)(2, 2) = 1.0 - q22;
    (*dphi_dr)(1, 0) = -mu * n1;
    (*dphi_dr)(2, 0) = -mu * n2;
    (*dphi_du)(1, 1) = rho * q11;
    (*dphi_du)(1, 2) = rho * q12;
    (*dphi_du)(2, 1) = rho * q12;
    (*dphi_du)(2, 2) = rho * q22;
    (*dphi_du)(1, 0) = mu * rho * n1;
    (*dphi_du)(2, 0) = mu * rho * n2;
  }
  return false;
}

double SemismoothNewtonSolver::merit(const ContactProblem& problem,
                                     const Eigen::Ref<const Eigen::VectorXd>& r,
                                     const Eigen::Ref<const Eigen::VectorXd>& u,
                                     Eigen::Ref<Eigen::VectorXd> phi) const {
  double sum = 0.0;
  for (int k = 0; k < problem.n_contacts; ++k) {
    Eigen::Vector3d uk = u.segment<3>(3 * k);
    uk[0] += problem.normal_bias[k];
    Eigen::Vector3d phik;
    contact_function(r.segment<3>(3 * k), uk, problem.friction[k], rho_[k], phik, nullptr, nullptr);
    phi.segment<3>(3 * k) = phik;
    sum += phik.squaredNorm();
  }
  return 0.5 * sum;
}

void SemismoothNewtonSolver::evaluate(const ContactProblem& problem,
                                      const Eigen::Ref<const Eigen::VectorXd>& r,
                                      const Eigen::Ref<const Eigen::VectorXd>& rho,
                                      Eigen::Ref<Eigen::VectorXd> phi,
                                      Eigen::Ref<Eigen::MatrixXd> jacobian) {
  const int n = problem.n_contacts, n3 = 3 * n;
  if (n3 > delassus_.rows() || rho.size() < n || r.size() < n3 || phi.size() < n3 ||
      jacobian.rows() < n3 || jacobian.cols() < n3) {
    std::ostringstream msg;
    msg << "SemismoothNewtonSolver::evaluate: " << n << " contacts, workspace for "
        << delassus_.rows() / 3 << ", or outputs too small";
    throw std::invalid_argument(msg.str());
  }
  problem.assemble_delassus_into(delassus_);
  auto w = delassus_.topLeftCorner(n3, n3);
  Eigen::VectorXd u = w * r.head(n3) + problem.free_velocity.head(n3);
  for (int k = 0; k < n; ++k) {
    Eigen::Vector3d uk = u.segment<3>(3 * k);
    uk[0] += problem.normal_bias[k];
    Eigen::Vector3d phik;
    Eigen::Matrix3d a, b;
    contact_function(r.segment<3>(3 * k), uk, problem.friction[k], rho[k], phik, &a, &b);
    phi.segment<3>(3 * k) = phik;
    jacobian.middleRows(3 * k, 3).leftCols(n3) = b * w.middleRows(3 * k, 3);
    jacobian.block<3, 3>(3 * k, 3 * k) += a;
  }
}

NewtonLinearSolve SemismoothNewtonSolver::linear_solve_for(const ContactProblem& problem,
                                                           NewtonLinearSolve requested) {
  const bool sparse = SparseNewtonSystem::applicable(problem);
  const bool woodbury = WoodburyNewtonSystem::applicable(problem);
  switch (requested) {
  case NewtonLinearSolve::dense:
    return NewtonLinearSolve::dense;
  case NewtonLinearSolve::sparse:
    return sparse ? NewtonLinearSolve::sparse : NewtonLinearSolve::dense;
  case NewtonLinearSolve::woodbury:
    return woodbury ? NewtonLinearSolve::woodbury : NewtonLinearSolve::dense;
  case NewtonLinearSolve::automatic:
    break;
  }
  if (sparse && SparseNewtonSystem::block_density(problem) <= kSparseDensity)
    return NewtonLinearSolve::sparse;
  if (woodbury &&
      WoodburyNewtonSystem::cost(problem) < iteration_cost(problem, NewtonLinearSolve::dense))
    return NewtonLinearSolve::woodbury;
  return NewtonLinearSolve::dense;
}

double SemismoothNewtonSolver::iteration_cost(const ContactProblem& problem,
                                              NewtonLinearSolve solve) {
  const double n = problem.n_contacts;
  switch (linear_solve_for(problem, solve)) {
  case NewtonLinearSolve::sparse:
    return kSparseBlockCost * SparseNewtonSystem::block_density(problem) * n * n;
  case NewtonLinearSolve::woodbury:
    return WoodburyNewtonSystem::cost(problem);
  default:
    return 2.0 / 3.0 * 27.0 * n * n * n + 54.0 * n * n;
  }
}

bool SemismoothNewtonSolver::solve_linear(const ContactProblem& problem, NewtonLinearSolve solve,
                                          int n_active, double delta) {
  const int m3 = 3 * n_active;
  auto rhs = rhs_.head(m3);
  if (solve == NewtonLinearSolve::sparse) {
    if (!sparse_.factorize(active_.data(), n_active, a_blocks_, b_blocks_, delta))
      return false;
    sparse_.solve(rhs);
    return true;
  }
  if (solve == NewtonLinearSolve::woodbury) {
    if (!woodbury_.factorize(problem, active_.data(), n_active, a_blocks_, b_blocks_, delta))
      return false;
    woodbury_.solve(problem, rhs);
    return true;
  }
  const int n3 = 3 * problem.n_contacts;
  const auto w = delassus_.topLeftCorner(n3, n3);
  auto jac = jacobian_.topLeftCorner(m3, m3);
  for (int i = 0; i < n_active; ++i) {
    const int ki = active_[i];
    const Eigen::Matrix3d b = b_blocks_.middleCols<3>(3 * ki);
    for (int j = 0; j < n_active; ++j)
      jac.block<3, 3>(3 * i, 3 * j).noalias() = b * w.block<3, 3>(3 * ki, 3 * active_[j]);
    jac.block<3, 3>(3 * i, 3 * i) += a_blocks_.middleCols<3>(3 * ki);
  }
  jac.diagonal().array() += delta;
  if (!lu_in_place(jac, pivots_.head(m3)))
    return false;
  lu_solve_in_place(jac, pivots_.head(m3), rhs);
  return true;
}

SolverResult SemismoothNewtonSolver::solve(const ContactProblem& problem,
                                           const SolverSettings& settings,
                                           Eigen::Ref<Eigen::VectorXd> p,
                                           DelassusProducts& products, StartProducts /*start*/,
                                           ResidualHistory& history) {
  const int n = problem.n_contacts, n3 = 3 * n;
  SolverResult result;
  const NewtonLinearSolve linear = linear_solve_for(problem, settings.newton_linear_solve);
  result.newton_linear_solve = linear;
  if (linear == NewtonLinearSolve::dense)
    problem.assemble_delassus_into(delassus_);
  else if (linear == NewtonLinearSolve::sparse)
    sparse_.prepare(problem);
  rho_.head(n) = settings.newton_rho_scale * products.eta.head(n);
  auto r = r_.head(n3);
  auto u = u_.head(n3);
  r = p.head(n3);
  auto apply_w = [&](const Eigen::Ref<const Eigen::VectorXd>& x, Eigen::Ref<Eigen::VectorXd> out) {
    problem.apply_delassus(x, apply_work_, out);
  };
  auto refresh_velocity = [&]() {
    apply_w(r, u);
    u += problem.free_velocity.head(n3);
  };
  // Projected onto the cones, with its velocity and residual: the returned iterate.
  auto finish = [&](bool project) {
    for (int k = 0; k < n; ++k) {
      const Eigen::Vector3d rk = r.segment<3>(3 * k);
      p.segment<3>(3 * k) = project ? project_onto_cone(rk, problem.friction[k]) : rk;
    }
    products.compute_velocity(problem, p);
    for (const CompliantPatch& patch : problem.patches) // for ContactSolver::patch_product()
      products.compute_patch_product(patch, p);
    result.residual = products.residual(problem, p, products.velocity);
    if (!std::isfinite(result.residual))
      result.status = SolverStatus::non_finite;
    else
      result.status = result.residual <= settings.tolerance ? SolverStatus::converged
                                                            : SolverStatus::max_iterations;
    return result;
  };

  refresh_velocity();
  result.residual = products.residual(problem, r, u);
  if (result.residual <= settings.tolerance)
    return finish(false);
  double theta = merit(problem, r, u, phi_);
  merits_.setConstant(theta);
  double delta = kDeltaMin;
  // The Levenberg-Marquardt floor below is engaged from the first short or rejected step, or
  // after kFloorAfter iterations, on: where full steps converge it would only slow them.
  bool floor_engaged = false;
  // Stall test (settings.newton_stall_iterations): the last halving of the residual.
  double halved = result.residual;
  int halved_at = 0;
  for (int it = 1; it <= settings.max_iterations; ++it) {
    result.iterations = it;
    if (it > kFloorAfter)
      floor_engaged = true;
    // Phi's Jacobian blocks; separated contacts leave the system (d_k = -r_k).
    int n_active = 0;
    for (int k = 0; k < n; ++k) {
      Eigen::Vector3d uk = u.segment<3>(3 * k);
      uk[0] += problem.normal_bias[k];
      Eigen::Vector3d phik;
      Eigen::Matrix3d a, b;
      separated_[k] =
          contact_function(r.segment<3>(3 * k), uk, problem.friction[k], rho_[k], phik, &a, &b) ? 1
                                                                                                : 0;
      a_blocks_.middleCols<3>(3 * k) = a;
      b_blocks_.middleCols<3>(3 * k) = b;
      step_.segment<3>(3 * k) = separated_[k] ? Eigen::Vector3d(-phik) : Eigen::Vector3d::Zero();
      if (!separated_[k])
        active_[n_active++] = k;
    }
    // W d for the separated part of the step.
    apply_w(step_.head(n3), w_step_.head(n3));
    // Levenberg-Marquardt floor of the regularisation: ||Phi|| / (||r|| + ||Phi||) (relative,
    // dimensionless), large far from a solution, vanishing at the rate of ||Phi|| near one.
    const double phi_norm = std::sqrt(2.0 * theta);
    const double delta_floor =
        floor_engaged
            ? std::min(kDeltaMax, kLevenbergMarquardt * phi_norm / (r.norm() + phi_norm + 1e-300))
            : 0.0;
    const int m3 = 3 * n_active;
    bool accepted = false;
    while (!accepted) {
      // (J_AA + delta I) d_A = -Phi_A - B_A W_AS d_S.
      for (int i = 0; i < n_active; ++i) {
        const int ki = active_[i];
        rhs_.segment<3>(3 * i) =
            -phi_.segment<3>(3 * ki) - b_blocks_.middleCols<3>(3 * ki) * w_step_.segment<3>(3 * ki);
      }
      if (m3 > 0) {
        if (!solve_linear(problem, linear, n_active, std::max(delta, delta_floor))) {
          if (delta >= kDeltaMax)
            return finish(true); // singular even at the largest regularisation
          delta = std::min(100.0 * delta, kDeltaMax);
          continue;
        }
        for (int i = 0; i < n_active; ++i)
          step_.segment<3>(3 * active_[i]) = rhs_.segment<3>(3 * i);
        apply_w(step_.head(n3), w_step_.head(n3));
      }
      // Non-monotone Armijo on 0.5 ||Phi||^2 (directional derivative -||Phi||^2 for the exact
      // Newton step).
      const double reference = merits_.maxCoeff();
      double t = 1.0, trial = 0.0;
      for (; t >= kMinStep; t *= 0.5) {
        trial_r_.head(n3) = r + t * step_.head(n3);
        trial_u_.head(n3) = u + t * w_step_.head(n3);
        trial = merit(problem, trial_r_.head(n3), trial_u_.head(n3), trial_phi_);
        if (trial <= reference - kArmijo * t * 2.0 * theta)
          break;
      }
      if (t >= kMinStep || delta >= kDeltaMax || !std::isfinite(trial)) {
        // Accepted (or, at the largest regularisation, the smallest step taken anyway). A full
        // step lowers the regularisation; a short one (the direction was poor: J nearly
        // singular) raises it for the next iteration.
        if (t < kMinStep)
          t = kMinStep;
        if (t == 1.0)
          delta = std::max(0.1 * delta, kDeltaMin);
        else if (t < kShortStep)
          delta = std::min(10.0 * delta, kDeltaMax);
        if (t < kShortStep)
          floor_engaged = true;
        r += t * step_.head(n3);
        u += t * w_step_.head(n3);
        accepted = true;
      } else {
        delta = std::min(100.0 * delta, kDeltaMax);
        floor_engaged = true;
        if (m3 == 0)
          break;
      }
    }
    if (it % kVelocityRefresh == 0)
      refresh_velocity();
    theta = merit(problem, r, u, phi_);
    merits_[it % kMeritMemory] = theta;
    result.residual = products.residual(problem, r, u);
    history.record(it, result.residual);
    if (!std::isfinite(result.residual))
      return finish(false);
    if (result.residual <= settings.tolerance) {
      finish(true);
      if (result.converged())
        return result;
      r = p.head(n3); // the projection cost accuracy: go on from the projected iterate
      refresh_velocity();
      theta = merit(problem, r, u, phi_);
    }
    if (result.residual < 0.5 * halved) {
      halved = result.residual;
      halved_at = it;
    } else if (settings.newton_stall_iterations > 0 &&
               it - halved_at >= settings.newton_stall_iterations) {
      break;
    }
  }
  return finish(true);
}

} // namespace plantar::contact
