#include "multibody/stepper.h"

#include "contact/compliance_terms.h"
#include "contact/flat_terrain.h"
#include "contact/ground_frame.h"
#include "contact/semidefinite_cholesky.h"
#include "multibody/configuration.h"
#include "multibody/crba.h"
#include "multibody/jacobian.h"
#include "multibody/kinematics.h"
#include "multibody/rnea.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <optional>
#include <sstream>
#include <stdexcept>

namespace plantar::multibody {

namespace {
/// Velocity (n, t1, t2) = R_c^T [I, -[r]x] twist of the point at lever r of a body with
/// origin twist (v_o, w) (world).
Eigen::Vector3d point_velocity(const Vector6d& t, const Eigen::Vector3d& r) {
  return Eigen::Vector3d(t[2] + r.y() * t[3] - r.x() * t[4], t[0] + r.z() * t[4] - r.y() * t[5],
                         t[1] - r.z() * t[3] + r.x() * t[5]);
}
} // namespace

void StepperParameters::validate() const {
  std::ostringstream msg;
  if (!(time_step > 0.0 && time_step <= 0.1)) {
    msg << "StepperParameters: time_step = " << time_step << " s, allowed (0, 0.1]";
  } else if (max_contacts < 0 || max_contacts > 100000) {
    msg << "StepperParameters: max_contacts = " << max_contacts << ", allowed [0, 100000]";
  } else if (!(contact_margin >= 0.0)) {
    msg << "StepperParameters: contact_margin = " << contact_margin << " m, allowed [0, inf]";
  } else if (!(theta >= 0.5 && theta <= 1.0)) {
    msg << "StepperParameters: theta = " << theta << ", allowed [0.5, 1]";
  } else if (!(passive_theta >= 0.5 && passive_theta <= 1.0)) {
    msg << "StepperParameters: passive_theta = " << passive_theta << ", allowed [0.5, 1]";
  }
  if (!msg.str().empty()) {
    throw std::invalid_argument(msg.str());
  }
  normal_bias.validate();
  solver.validate();
}

Stepper::Stepper(const Model& model, const StepperParameters& parameters)
    : Stepper(model, parameters, contact::flat_ground()) {}

Stepper::Stepper(const Model& model, const StepperParameters& parameters,
                 const contact::Terrain& terrain)
    : model_(model), parameters_(parameters), terrain_(&terrain), data_(model),
      gains_(PdGains::Zero(model)), body_slot_(model.n_bodies, -1) {
  parameters_.validate();
  const std::optional<double> level = terrain.level_height();
  level_ground_ = level.has_value();
  level_ = level.value_or(0.0);
  dof_theta_.setConstant(model.nv, parameters_.theta);
  for (int iv = 0; iv < model.nv; ++iv)
    if (model.passive_stiffness[iv] > 0.0 || model.passive_damping[iv] > 0.0)
      dof_theta_[iv] = parameters_.passive_theta;
  resize_workspaces();
}

void Stepper::resize_workspaces() {
  const int nv = model_.nv;
  const int max = parameters_.max_contacts;
  effective_mass_.setZero(nv, nv);
  factorization_ = TreeFactorization(model_);
  dense_factor_.setZero(parameters_.tree_factorization ? 0 : nv,
                        parameters_.tree_factorization ? 0 : nv);
  rhs_.setZero(nv);
  v_free_.setZero(nv);
  dv_.setZero(nv);
  bias_start_.setZero(nv);
  v_mid_.setZero(nv);
  impulses_.setZero(3 * max);
  warm_start_.setZero(3 * max);
  // The contact rows see only the contact bodies' 6-dof motions: a rigid factor of rank
  // 6 x (contact bodies) instead of nv when that is smaller.
  const int n_slots = static_cast<int>(slot_body_.size());
  reduce_rigid_ = 6 * n_slots < nv;
  const int rank = reduce_rigid_ ? 6 * n_slots : nv;
  reduced_gram_.setZero(rank, rank);
  reduced_slots_.reserve(n_slots);
  for (auto& z : slot_reduced_) {
    z.setZero(6, rank);
  }
  problem_.resize(max, rank);
  for (auto& patch : problem_.patch_levers) {
    patch.lever_map.setZero(6, rank);
    patch.lever_map_valid = false;
  }
  solver_.resize(max, rank, parameters_.solver.solver);
  gap_.setZero(points_.size());
  v_before_.setZero(points_.size());
  lever_.assign(points_.size(), Eigen::Vector3d::Zero());
  frame_.assign(points_.size(), contact::ground_frame());
  active_points_.reserve(points_.size());
}

bool Stepper::factor_effective_mass() {
  if (parameters_.tree_factorization)
    return factorization_.compute(effective_mass_);
  // Eigen's unblocked kernel (at nv ~ 40 faster than LLT::compute's blocked one).
  dense_factor_ = effective_mass_;
  return Eigen::internal::llt_inplace<double, Eigen::Lower>::unblocked(dense_factor_) < 0;
}

void Stepper::half_solve(Eigen::Ref<Eigen::MatrixXd> x) const {
  if (parameters_.tree_factorization)
    factorization_.half_solve_in_place(x); // on the nonzero rows' ancestors only
  else
    dense_factor_.triangularView<Eigen::Lower>().solveInPlace(x);
}

void Stepper::half_solve_transpose(Eigen::Ref<Eigen::MatrixXd> x) const {
  if (parameters_.tree_factorization)
    factorization_.half_solve_transpose_in_place(x);
  else
    dense_factor_.triangularView<Eigen::Lower>().transpose().solveInPlace(x);
}

void Stepper::solve_effective_mass(Eigen::VectorXd& x) const {
  half_solve(x);
  half_solve_transpose(x);
}

int Stepper::add_body_slot(int body) {
  if (body_slot_[body] < 0) {
    const int nv = model_.nv;
    body_slot_[body] = static_cast<int>(slot_body_.size());
    slot_body_.push_back(body);
    slot_jacobian_.push_back(Eigen::Matrix<double, 6, Eigen::Dynamic>::Zero(6, nv));
    slot_factor_.push_back(Eigen::MatrixXd::Zero(nv, 6));
    slot_factor_t_.push_back(Eigen::Matrix<double, 6, Eigen::Dynamic>::Zero(6, nv));
    slot_velocity_.push_back(Vector6d::Zero());
    slot_free_velocity_.push_back(Vector6d::Zero());
    slot_impulse_.push_back(Vector6d::Zero());
    slot_factored_.push_back(0);
    slot_reduced_.emplace_back();
    std::vector<int> dofs;
    for (int j = body; j > 0; j = model_.parent[j]) {
      for (int k = model_.nv_joint[j] - 1; k >= 0; --k) {
        dofs.push_back(model_.idx_v[j] + k);
      }
    }
    std::reverse(dofs.begin(), dofs.end());
    slot_dofs_.push_back(dofs);
  }
  return body_slot_[body];
}

void Stepper::set_gains(const PdGains& gains) {
  gains.validate(model_);
  gains_ = gains;
}

int Stepper::add_contact_point(int body, const Eigen::Vector3d& position, double friction) {
  if (body < 0 || body >= model_.n_bodies) {
    throw std::invalid_argument("Stepper::add_contact_point: body " + std::to_string(body) +
                                ", allowed [0, " + std::to_string(model_.n_bodies) + ")");
  }
  if (!(friction >= 0.0) || !std::isfinite(friction)) {
    throw std::invalid_argument("Stepper::add_contact_point: friction " + std::to_string(friction) +
                                ", allowed [0, inf)");
  }
  if (static_cast<int>(points_.size()) + 1 > parameters_.max_contacts) {
    throw std::invalid_argument("Stepper::add_contact_point: more than max_contacts = " +
                                std::to_string(parameters_.max_contacts) + " contact points");
  }
  points_.push_back(ContactPoint{body, position, friction});
  point_impulse_.push_back(Eigen::Vector3d::Zero());
  add_body_slot(body);
  resize_workspaces();
  return static_cast<int>(points_.size()) - n_patch_points_ - 1;
}

int Stepper::add_deformable_patch(int body, const Eigen::Matrix3Xd& nodes, double friction,
                                  contact::DeformablePatch& patch) {
  const int n = static_cast<int>(nodes.cols());
  if (body < 0 || body >= model_.n_bodies || n == 0 || patch.n_nodes() != n || !(friction >= 0.0)) {
    std::ostringstream msg;
    msg << "Stepper::add_deformable_patch: body " << body << " (allowed [0, " << model_.n_bodies
        << ")), " << n << " nodes (allowed >= 1, the patch's " << patch.n_nodes() << "), friction "
        << friction << " (allowed [0, inf))";
    throw std::invalid_argument(msg.str());
  }
  for (int i = body; i > 0; i = model_.parent[i]) { // the joints that move the patch
    if ((dof_theta_.segment(model_.idx_v[i], model_.nv_joint[i]).array() != parameters_.theta)
            .any()) {
      std::ostringstream msg;
      msg << "Stepper::add_deformable_patch: body " << body << " is moved by the passive joint "
          << model_.joint_names[i] << " and passive_theta = " << parameters_.passive_theta
          << " differs from theta = " << parameters_.theta
          << " (a patch's node velocity follows one theta; allowed: equal values)";
      throw std::invalid_argument(msg.str());
    }
  }
  if (static_cast<int>(points_.size()) + n > parameters_.max_contacts) {
    throw std::invalid_argument(
        "Stepper::add_deformable_patch: " + std::to_string(n) +
        " more nodes exceed max_contacts = " + std::to_string(parameters_.max_contacts));
  }
  // Patch nodes go before the free points, after the previous patches' nodes.
  std::vector<ContactPoint> nodes_as_points;
  for (int k = 0; k < n; ++k) {
    nodes_as_points.push_back(ContactPoint{body, nodes.col(k), friction});
  }
  points_.insert(points_.begin() + n_patch_points_, nodes_as_points.begin(), nodes_as_points.end());
  // first_point of later patches cannot change: patches are appended in order.
  point_impulse_.insert(point_impulse_.begin() + n_patch_points_, n, Eigen::Vector3d::Zero());
  patches_.push_back(Patch{body, nodes, n_patch_points_, &patch});
  n_patch_points_ += n;
  add_body_slot(body);
  problem_.patches.push_back(contact::CompliantPatch{});
  // The patch's rigid rows are (I (x) a) Lambda T with Lambda's node rows [I, -[rho]x] (body
  // frame) and T = blockdiag(R_b^T, R_b^T) H_b: the structure of the direct sticking solve.
  problem_.patch_levers.emplace_back();
  contact::set_sticking_structure(problem_.patch_levers.back(), contact::rigid_lever(nodes));
  const int index = static_cast<int>(patches_.size()) - 1;
  patch.attach(problem_, index, parameters_.time_step, parameters_.theta);
  resize_workspaces();
  return index;
}

double Stepper::evaluate_candidate(int point, double extra_gap) {
  const ContactPoint& c = points_[point];
  const SE3& placement = data_.oMi[c.body];
  const Eigen::Vector3d r = placement.rotation * c.position;
  lever_[point] = r;
  const int s = body_slot_[c.body];
  const Vector6d& vel = slot_velocity_[s];
  const Vector6d& free = slot_free_velocity_[s];
  if (level_ground_) {
    gap_[point] = ((r + placement.translation).z() - level_) + extra_gap;
    // Normal (z) velocity of the point: v_o,z + (w x r)_z.
    v_before_[point] = vel[2] + (vel[3] * r.y() - vel[4] * r.x());
    return free[2] + (free[3] * r.y() - free[4] * r.x());
  }
  // The terrain's gap and frame at the point (x, y); normal velocity n . (v_o + w x r).
  const contact::TerrainContact ground =
      contact::terrain_contact(*terrain_, r + placement.translation);
  frame_[point] = ground.frame;
  gap_[point] = ground.gap + extra_gap;
  const Eigen::Vector3d normal = ground.frame.col(0);
  v_before_[point] = normal.dot(vel.head<3>() + vel.tail<3>().cross(r));
  return normal.dot(free.head<3>() + free.tail<3>().cross(r));
}

Eigen::Vector3d Stepper::contact_velocity(int point, const Vector6d& twist) const {
  if (level_ground_)
    return point_velocity(twist, lever_[point]);
  return frame_[point].transpose() * (twist.head<3>() + twist.tail<3>().cross(lever_[point]));
}

Eigen::Vector3d Stepper::to_world(int point, const Eigen::Vector3d& c) const {
  if (level_ground_)
    return contact::ground_to_world(c);
  return frame_[point] * c;
}

void Stepper::fill_contact_rows(int k, int point) {
  const int s = body_slot_[points_[point].body];
  // Rows S(r) (J_b U^-T) with S(r) = R_c^T [I, -[r]x], contact frame rows n = z, t1 = x,
  // t2 = y, written out (the zeros of S skipped): row n = H_2 + r_y H_3 - r_x H_4,
  // t1 = H_0 + r_z H_4 - r_y H_5, t2 = H_1 - r_z H_3 + r_x H_5, H = J_b U^-T.
  const Eigen::Vector3d& r = lever_[point];
  const Eigen::Matrix<double, 6, Eigen::Dynamic>& h =
      reduce_rigid_ ? slot_reduced_[s] : slot_factor_t_[s];
  Eigen::MatrixXd& g = problem_.rigid_factor;
  if (level_ground_) {
    for (int col = 0; col < g.cols(); ++col) {
      const double* hc = h.col(col).data();
      double* gc = g.col(col).data() + 3 * k;
      gc[0] = hc[2] + r.y() * hc[3] - r.x() * hc[4];
      gc[1] = hc[0] + r.z() * hc[4] - r.y() * hc[5];
      gc[2] = hc[1] - r.z() * hc[3] + r.x() * hc[5];
    }
  } else { // the terrain frame: rows R_c^T (H_0..2 + H_3..5 x r)
    const Eigen::Matrix3d rt = frame_[point].transpose();
    for (int col = 0; col < g.cols(); ++col) {
      const double* hc = h.col(col).data();
      const Eigen::Vector3d u(hc[0] + hc[4] * r.z() - hc[5] * r.y(),
                              hc[1] + hc[5] * r.x() - hc[3] * r.z(),
                              hc[2] + hc[3] * r.y() - hc[4] * r.x());
      double* gc = g.col(col).data() + 3 * k;
      gc[0] = rt(0, 0) * u[0] + rt(0, 1) * u[1] + rt(0, 2) * u[2];
      gc[1] = rt(1, 0) * u[0] + rt(1, 1) * u[1] + rt(1, 2) * u[2];
      gc[2] = rt(2, 0) * u[0] + rt(2, 1) * u[1] + rt(2, 2) * u[2];
    }
  }
  problem_.free_velocity.segment<3>(3 * k) = contact_velocity(point, slot_free_velocity_[s]);
}

void Stepper::reduce_rigid_factor() {
  // H H^T over the slots in contact (6 r x 6 r), then Z Z^T = H H^T by a Cholesky that keeps
  // the semi-definite case (a pivot below 1e-13 of the largest diagonal: zero column).
  const int r = static_cast<int>(reduced_slots_.size());
  const int size = 6 * r;
  auto gram = reduced_gram_.topLeftCorner(size, size);
  // H_i H_j^T over the rows where both are nonzero: the common ancestors' dofs (both lists
  // ascend from the root, so they share a prefix). The dense factor fills in: all rows.
  for (int i = 0; i < r && !parameters_.tree_factorization; ++i) {
    for (int j = 0; j <= i; ++j) {
      gram.block<6, 6>(6 * i, 6 * j).noalias() =
          slot_factor_t_[reduced_slots_[i]] * slot_factor_[reduced_slots_[j]];
    }
  }
  for (int i = 0; i < r && parameters_.tree_factorization; ++i) {
    const std::vector<int>& dofs_i = slot_dofs_[reduced_slots_[i]];
    const Eigen::Matrix<double, 6, Eigen::Dynamic>& h_i = slot_factor_t_[reduced_slots_[i]];
    for (int j = 0; j <= i; ++j) {
      const std::vector<int>& dofs_j = slot_dofs_[reduced_slots_[j]];
      const Eigen::Matrix<double, 6, Eigen::Dynamic>& h_j = slot_factor_t_[reduced_slots_[j]];
      Eigen::Matrix<double, 6, 6> block = Eigen::Matrix<double, 6, 6>::Zero();
      const std::size_t common = std::min(dofs_i.size(), dofs_j.size());
      for (std::size_t k = 0; k < common && dofs_i[k] == dofs_j[k]; ++k) {
        block.noalias() += h_i.col(dofs_i[k]) * h_j.col(dofs_i[k]).transpose();
      }
      gram.block<6, 6>(6 * i, 6 * j) = block;
    }
  }
  contact::semidefinite_cholesky(gram, 1e-13);
  for (int i = 0; i < r; ++i) {
    Eigen::Matrix<double, 6, Eigen::Dynamic>& z = slot_reduced_[reduced_slots_[i]];
    z.setZero();
    z.leftCols(size) = gram.middleRows<6>(6 * i);
    for (int row = 0; row < 6; ++row) { // the strict upper triangle holds H H^T: not Z
      z.row(row).segment(6 * i + row + 1, size - 6 * i - row - 1).setZero();
    }
  }
}

void Stepper::lap(double& bucket) {
  const auto now = std::chrono::steady_clock::now();
  bucket += std::chrono::duration<double>(now - lap_start_).count();
  lap_start_ = now;
}

StepReport Stepper::step(Eigen::Ref<Eigen::VectorXd> q, Eigen::Ref<Eigen::VectorXd> v,
                         const Eigen::Ref<const Eigen::VectorXd>& tau,
                         const Eigen::Ref<const Eigen::VectorXd>& q_ref,
                         const Eigen::Ref<const Eigen::VectorXd>& v_ref) {
  check_size(q.size(), model_.nq, "Stepper::step: q");
  check_size(v.size(), model_.nv, "Stepper::step: v");
  check_size(tau.size(), model_.nv, "Stepper::step: tau");
  check_size(q_ref.size(), model_.nq, "Stepper::step: q_ref");
  check_size(v_ref.size(), model_.nv, "Stepper::step: v_ref");
  const double dt = parameters_.time_step;
  StepReport report;
  lap_start_ = std::chrono::steady_clock::now();
  ++profile_.n_steps;

  free_motion(q, v, tau, q_ref, v_ref);
  lap(profile_.dynamics);
  const int n = select_candidates();
  report.n_contacts = n;
  problem_.n_contacts = n;
  if (n > 0) {
    assemble(n, v);
    warm_start_.head(3 * n) = impulses_.head(3 * n);
    report.solver = solver_.solve(problem_, parameters_.solver, impulses_);
    lap(profile_.contact_solve);
    ++profile_.n_solves;
    profile_.n_solve_rows += 3 * n;
    if (report.solver.status == contact::SolverStatus::non_finite) {
      throw std::runtime_error("Stepper::step: the contact solver produced non-finite impulses "
                               "with " +
                               std::to_string(n) + " contacts");
    }
    if (parameters_.throw_if_not_converged) {
      contact::throw_if_not_converged(report.solver, parameters_.solver, "Stepper::step");
    }
  } else {
    report.solver.status = contact::SolverStatus::converged;
  }
  apply_impulses(n, v);
  lap(profile_.dynamics);
  // Impulses of the step: the patches' (their state renewed), then the free points'.
  for (const Patch& patch : patches_) {
    patch.state->finish_step(impulses_, solver_, report.solver, &point_impulse_[patch.first_point]);
  }
  for (int point = n_patch_points_; point < static_cast<int>(points_.size()); ++point) {
    point_impulse_[point].setZero();
  }
  for (int k = 0; k < n; ++k) {
    if (active_points_[k] >= n_patch_points_) {
      point_impulse_[active_points_[k]] += impulses_.segment<3>(3 * k);
    }
  }
  lap(profile_.sole_update);
  if (!v.allFinite()) {
    throw std::runtime_error(
        "Stepper::step: non-finite velocity after the step (dt = " + std::to_string(dt) + " s)");
  }
  integrate(model_, q, v_mid_, dt, q);
  lap(profile_.dynamics);
  return report;
}

void Stepper::free_motion(const Eigen::Ref<const Eigen::VectorXd>& q,
                          const Eigen::Ref<const Eigen::VectorXd>& v,
                          const Eigen::Ref<const Eigen::VectorXd>& tau,
                          const Eigen::Ref<const Eigen::VectorXd>& q_ref,
                          const Eigen::Ref<const Eigen::VectorXd>& v_ref) {
  const double dt = parameters_.time_step;
  const double theta = parameters_.theta;
  // Free motion with linear-implicit springs at theta: M_eff v_free = r.
  nonlinear_effects(model_, data_, q, v); // also fills liMi, oMi, v
  crba_from_placements(model_, data_);
  effective_mass_ = data_.mass_matrix;
  rhs_.noalias() = data_.mass_matrix * v;
  rhs_ += dt * (tau - data_.bias);
  const double lag = (1.0 - theta) * dt; // q_theta = q + theta (lag v + theta dt v+)
  for (int i = 1; i < model_.n_bodies; ++i) {
    if (model_.joint_type[i] == JointType::FreeFlyer) {
      continue;
    }
    const int iq = model_.idx_q[i];
    const int iv = model_.idx_v[i];
    const double kp = gains_.stiffness[iv];
    const double kd = gains_.damping[iv];
    const double ks = model_.passive_stiffness[iv];
    const double ds = model_.passive_damping[iv];
    if (parameters_.implicit_gains) {
      const double th = dof_theta_[iv]; // theta, or passive_theta for a passive joint
      const double lag_j = (1.0 - th) * dt, th_dt = th * dt;
      const double q_lag = q[iq] + th * lag_j * v[iv];
      const double spring =
          kp * (q_ref[iq] - lag_j * v_ref[iv] - q_lag) + ks * (model_.passive_rest[iv] - q_lag);
      effective_mass_(iv, iv) += th_dt * (kd + ds) + th_dt * th_dt * (kp + ks);
      rhs_[iv] += dt * (spring + kd * v_ref[iv] - (1.0 - th) * (kd + ds) * v[iv]);
    } else {
      const double spring = kp * (q_ref[iq] - q[iq]) + ks * (model_.passive_rest[iv] - q[iq]);
      rhs_[iv] += dt * (spring + kd * (v_ref[iv] - v[iv]) - ds * v[iv]);
    }
  }
  // The contact bodies' Jacobians; theta < 1: the patch forces of the last step's end act over
  // (1 - theta) of this step, a known generalized force J_b^T (f, r x f).
  for (std::size_t s = 0; s < slot_body_.size(); ++s) {
    body_origin_jacobian(model_, data_, slot_body_[s], slot_jacobian_[s]);
    slot_velocity_[s].noalias() = slot_jacobian_[s] * v;
    slot_impulse_[s].setZero();
  }
  bool any_force = false;
  for (const Patch& patch : patches_) {
    if (!patch.state->has_force() || theta == 1.0) {
      continue;
    }
    any_force = true;
    const SE3& placement = data_.oMi[patch.body];
    Vector6d& wrench = slot_impulse_[body_slot_[patch.body]];
    const Eigen::VectorXd& force = patch.state->force();
    for (int k = 0; k < patch.nodes.cols(); ++k) { // in the last step's frames
      const Eigen::Vector3d world = to_world(patch.first_point + k, force.segment<3>(3 * k));
      const Eigen::Vector3d r = placement.rotation * patch.nodes.col(k);
      wrench.head<3>() += lag * world;
      wrench.tail<3>() += r.cross(lag * world);
    }
  }
  if (any_force) {
    for (std::size_t s = 0; s < slot_body_.size(); ++s) {
      rhs_.noalias() += slot_jacobian_[s].transpose() * slot_impulse_[s];
    }
  }
  // M_eff = U U^T: along the tree (M_eff has M's sparsity: the gains are diagonal) or dense.
  if (!factor_effective_mass()) {
    throw std::runtime_error("Stepper::step: M + dt D + dt^2 K is not positive definite "
                             "(check the model's inertias and the gains)");
  }
  v_free_ = rhs_;
  solve_effective_mass(v_free_);
  if (parameters_.midpoint_bias) {
    // Second pass: b evaluated at v_mid = (v + v_free) / 2 instead of v.
    bias_start_ = data_.bias;
    v_mid_ = 0.5 * (v + v_free_);
    nonlinear_effects(model_, data_, q, v_mid_);
    rhs_ += dt * (bias_start_ - data_.bias);
    v_free_ = rhs_;
    solve_effective_mass(v_free_);
  }
}

int Stepper::select_candidates() {
  const double dt = parameters_.time_step;
  const double margin = parameters_.contact_margin;
  // Patches first (all nodes when any is active), then free points. Per body carrying
  // candidates: J_b, J_b v and J_b v_free once.
  for (std::size_t s = 0; s < slot_body_.size(); ++s) {
    slot_free_velocity_[s].noalias() = slot_jacobian_[s] * v_free_;
    slot_factored_[s] = 0;
  }
  int n = 0;
  active_points_.clear();
  for (Patch& patch : patches_) {
    contact::DeformablePatch& state = *patch.state;
    const int n_nodes = static_cast<int>(patch.nodes.cols());
    const Eigen::VectorXd& displacement = state.displacement();
    bool any_active = false;
    for (int k = 0; k < n_nodes; ++k) {
      const int point = patch.first_point + k;
      const double v_free_n = evaluate_candidate(point, displacement[3 * k]);
      // With no impulse the node's deformation relaxes to the offset d within the step (the
      // -(U_prev - d)/dt term of eq. 12), so the node can touch iff the unloaded gap
      // g - U_prev + d does (d of the last step's frames).
      any_active =
          any_active || state.unloaded_gap(k, gap_[point]) + dt * std::min(v_free_n, 0.0) <= margin;
    }
    if (!any_active) {
      state.deactivate(n);
      continue;
    }
    lap(profile_.contact_build);
    state.activate(n, contact::ground_frame_transpose() * data_.oMi[patch.body].rotation,
                   level_ground_ ? nullptr : &frame_[patch.first_point],
                   &point_impulse_[patch.first_point]);
    lap(profile_.sole_update);
    for (int k = 0; k < n_nodes; ++k) {
      active_points_.push_back(patch.first_point + k);
    }
    n += n_nodes;
  }
  for (int point = n_patch_points_; point < static_cast<int>(points_.size()); ++point) {
    const double v_free_n = evaluate_candidate(point, 0.0);
    if (gap_[point] + dt * std::min(v_free_n, 0.0) <= margin) {
      active_points_.push_back(point);
      ++n;
    }
  }
  return n;
}

void Stepper::assemble(int n, const Eigen::Ref<const Eigen::VectorXd>& v) {
  const double dt = parameters_.time_step;
  const double theta = parameters_.theta;
  const double theta_dt = theta * dt;
  // U^-1 J_b^T once per body in contact; the reduced rigid factor over those bodies.
  reduced_slots_.clear();
  for (int k = 0; k < n; ++k) {
    const int s = body_slot_[points_[active_points_[k]].body];
    if (!slot_factored_[s]) {
      slot_factor_[s] = slot_jacobian_[s].transpose();
      half_solve(slot_factor_[s]);
      slot_factor_t_[s] = slot_factor_[s].transpose();
      slot_factored_[s] = 1;
      reduced_slots_.push_back(s);
    }
  }
  if (reduce_rigid_) {
    reduce_rigid_factor();
  }
  // T = blockdiag(R_b^T, R_b^T) H_b of each patch in contact (PatchLever::lever_map).
  for (std::size_t j = 0; j < patches_.size(); ++j) {
    contact::PatchLever& target = problem_.patch_levers[j];
    target.lever_map_valid = problem_.patches[j].n_contacts > 0;
    if (target.lever_map_valid) {
      const int s = body_slot_[patches_[j].body];
      const Eigen::Matrix<double, 6, Eigen::Dynamic>& h =
          reduce_rigid_ ? slot_reduced_[s] : slot_factor_t_[s];
      const Eigen::Matrix3d& rotation = data_.oMi[patches_[j].body].rotation;
      target.lever_map.topRows<3>().noalias() = rotation.transpose() * h.topRows<3>();
      target.lever_map.bottomRows<3>().noalias() = rotation.transpose() * h.bottomRows<3>();
    }
  }
  // G (3 n x rank), v_free,c, b, mu, warm start.
  for (int k = 0; k < n; ++k) {
    const int point = active_points_[k];
    fill_contact_rows(k, point);
    const double gap = gap_[point];
    // An impact with restitution follows Newton's law alone (Moreau-Jean); otherwise a
    // contact activated before touching may close its gap within the step, no more:
    // normal_bias returns gap/dt for gap > 0 (adding it again let a landing sink by the gap).
    // A patch node's velocity is (x+ - x) / (theta dt) = v+ + (1-theta)/theta v (theta-mixed
    // position update), so its gap is closed over theta dt.
    const bool node = point < n_patch_points_;
    problem_.normal_bias[k] =
        contact::normal_bias(gap, v_before_[point], node ? theta_dt : dt, parameters_.normal_bias);
    if (node && theta < 1.0) {
      problem_.free_velocity.segment<3>(3 * k) +=
          ((1.0 - theta) / theta) *
          contact_velocity(point, slot_velocity_[body_slot_[points_[point].body]]);
    }
    problem_.friction[k] = points_[point].friction;
    impulses_.segment<3>(3 * k) = point_impulse_[point];
  }
  lap(profile_.contact_build);
  for (std::size_t j = 0; j < patches_.size(); ++j) {
    if (problem_.patches[j].n_contacts > 0) {
      patches_[j].state->add_rate_terms();
    }
  }
  lap(profile_.sole_update);
}

void Stepper::apply_impulses(int n, Eigen::Ref<Eigen::VectorXd> v) {
  if (n == 0) {
    v_mid_ = v + dof_theta_.cwiseProduct(v_free_ - v);
    v = v_free_;
    return;
  }
  // v+ = v_free + U^-T (G^T p), G^T p = sum over bodies of (U^-1 J_b^T) (sum of S^T p).
  for (auto& impulse : slot_impulse_) {
    impulse.setZero();
  }
  for (int k = 0; k < n; ++k) {
    const Eigen::Vector3d world = to_world(active_points_[k], impulses_.segment<3>(3 * k));
    Vector6d& wrench = slot_impulse_[body_slot_[points_[active_points_[k]].body]];
    wrench.head<3>() += world;
    wrench.tail<3>() += lever_[active_points_[k]].cross(world);
  }
  dv_.setZero();
  for (std::size_t s = 0; s < slot_body_.size(); ++s) {
    if (slot_factored_[s]) {
      dv_.noalias() += slot_factor_[s] * slot_impulse_[s];
    }
  }
  half_solve_transpose(dv_);
  dv_ += v_free_;                                // v+
  v_mid_ = v + dof_theta_.cwiseProduct(dv_ - v); // v_theta
  v = dv_;
}

Eigen::Vector3d Stepper::total_contact_force() const {
  Eigen::Vector3d sum = Eigen::Vector3d::Zero();
  for (std::size_t point = 0; point < point_impulse_.size(); ++point) {
    sum += to_world(static_cast<int>(point), point_impulse_[point]);
  }
  return sum / parameters_.time_step;
}

} // namespace plantar::multibody
