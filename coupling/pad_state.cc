#include "coupling/pad_state.h"

#include "contact/compliance_terms.h"
#include "contact/ground_frame.h"
#include "contact/symmetry.h"

#include <cmath>
#include <sstream>
#include <stdexcept>

namespace plantar::coupling {

PadState::PadState(const Eigen::Ref<const Eigen::MatrixXd>& compliance) : compliance_(compliance) {
  const Eigen::Index size = compliance.rows();
  if (size == 0 || size % 3 != 0 || compliance.cols() != size || !compliance.allFinite()) {
    std::ostringstream msg;
    msg << "PadState: compliance " << compliance.rows() << "x" << compliance.cols()
        << " (expected 3 n x 3 n, n >= 1, finite)";
    throw std::invalid_argument(msg.str());
  }
  contact::check_symmetric(compliance, "PadState", "compliance");
  const Eigen::VectorXd zero = Eigen::VectorXd::Zero(size);
  node_rotations_.setZero(3, size);
  frames_.setZero(3, size);
  displacement_ = offset_ = offset_contact_ = product_ = impulse_ = force_ = elastic_ =
      relaxation_ = zero;
}

void PadState::attach(contact::ContactProblem& problem, int index, double time_step, double theta) {
  problem_ = &problem;
  index_ = index;
  time_step_ = time_step;
  theta_ = theta;
  parked_ = compliance_ / std::pow(theta * time_step, 2);
  block().warm_product.setZero(compliance_.rows());
  block().node_rotations.setZero(3, compliance_.rows());
}

void PadState::set_block() {
  const double dt = time_step_, theta = theta_;
  const double a = theta / (damping_ / dt + theta);
  Eigen::MatrixXd& held =
      block().compliance_over_dt.size() != 0 ? block().compliance_over_dt : parked_;
  held = compliance_ * (a / ((theta * dt) * (theta * dt)));
  contact::set_sticking_structure(problem_->patch_levers[index_],
                                  problem_->patch_levers[index_].lever);
  has_last_solve_ = false;
}

void PadState::set_compliance(const Eigen::Ref<const Eigen::MatrixXd>& compliance,
                              const Eigen::Ref<const Eigen::VectorXd>& offset) {
  const Eigen::Index size = compliance_.rows();
  if (compliance.rows() != size || compliance.cols() != size || offset.size() != size ||
      !compliance.allFinite() || !offset.allFinite()) {
    std::ostringstream msg;
    msg << "PadState::set_compliance: compliance " << compliance.rows() << "x" << compliance.cols()
        << " and offset " << offset.size() << " (expected " << size << "x" << size << " and "
        << size << ", finite)";
    throw std::invalid_argument(msg.str());
  }
  contact::check_symmetric(compliance, "PadState::set_compliance", "compliance");
  if (damping_ > 0.0 && !offset.isZero(0.0))
    throw std::invalid_argument("PadState::set_compliance: the pad is damped (set_damping): an "
                                "offset d is not supported");
  compliance_ = compliance;
  offset_ = offset;
  has_offset_ = !offset.isZero(0.0);
  if (problem_ != nullptr)
    set_block();
  if (has_offset_) {
    for (int k = 0; k < size / 3; ++k)
      offset_contact_.segment<3>(3 * k).noalias() = node_rotation(k) * offset_.segment<3>(3 * k);
  }
}

Eigen::Vector3d PadState::node_to_world(int node, const Eigen::Vector3d& c) const {
  if (per_node_)
    return frames_.middleCols<3>(3 * node) * c;
  return contact::ground_to_world(c);
}

void PadState::set_offset(const Eigen::Ref<const Eigen::VectorXd>& offset) {
  if (offset.size() != compliance_.rows() || !offset.allFinite()) {
    std::ostringstream msg;
    msg << "PadState::set_offset: offset of size " << offset.size() << " (expected "
        << compliance_.rows() << ", finite)";
    throw std::invalid_argument(msg.str());
  }
  if (damping_ > 0.0)
    throw std::invalid_argument("PadState::set_offset: the pad is damped (set_damping): an "
                                "offset d is not supported");
  offset_ = offset;
  has_offset_ = true;
  for (int k = 0; k < n_nodes(); ++k)
    offset_contact_.segment<3>(3 * k).noalias() = node_rotation(k) * offset_.segment<3>(3 * k);
}

void PadState::set_damping(double beta) {
  if (!(beta >= 0.0) || !std::isfinite(beta)) {
    std::ostringstream msg;
    msg << "PadState::set_damping: beta = " << beta << " s, allowed [0, inf)";
    throw std::invalid_argument(msg.str());
  }
  if (beta > 0.0 && has_offset_)
    throw std::invalid_argument("PadState::set_damping: the pad has an offset d (affine pad "
                                "model): damping is not supported");
  damping_ = beta;
  if (problem_ != nullptr)
    set_block();
}

void PadState::deactivate(int first_contact) {
  contact::CompliantPatch& target = block();
  if (target.compliance_over_dt.size() != 0)
    target.compliance_over_dt.swap(parked_);
  target.first_contact = first_contact;
  target.n_contacts = 0;
  if (lifted_offset_ && has_offset_) // U = C 0 + d: the free recovery
    displacement_ = offset_contact_;
  else
    displacement_.setZero(); // a massless pad relaxes when lifted
  elastic_.setZero();
  has_last_solve_ = false;
}

void PadState::activate(int first_contact, const Eigen::Matrix3d& rotation,
                        const Eigen::Matrix3d* node_frames, Eigen::Vector3d* warm_start) {
  contact::CompliantPatch& target = block();
  if (target.compliance_over_dt.size() == 0)
    target.compliance_over_dt.swap(parked_);
  target.first_contact = first_contact;
  const int n = n_nodes();
  target.n_contacts = n;
  rotation_ = rotation;
  if (node_frames != nullptr) {
    // a_k = R_c,k^T R_body; the last displacements, C F and forces carried into the new
    // frames: U <- R_c,k^T R_c,k,old U (world vectors kept).
    const Eigen::Matrix3d body = contact::ground_frame() * rotation;
    for (int k = 0; k < n; ++k) {
      const Eigen::Matrix3d old_frame =
          per_node_ ? Eigen::Matrix3d(frames_.middleCols<3>(3 * k)) : contact::ground_frame();
      const Eigen::Matrix3d change = node_frames[k].transpose() * old_frame;
      displacement_.segment<3>(3 * k) = change * displacement_.segment<3>(3 * k);
      elastic_.segment<3>(3 * k) = change * elastic_.segment<3>(3 * k);
      force_.segment<3>(3 * k) = change * force_.segment<3>(3 * k);
      frames_.middleCols<3>(3 * k) = node_frames[k];
      node_rotations_.middleCols<3>(3 * k).noalias() = node_frames[k].transpose() * body;
    }
    per_node_ = true;
    target.node_rotations = node_rotations_; // same size: no allocation
  } else {
    per_node_ = false;
  }
  target.per_node_rotations = per_node_;
  if (has_last_solve_) {
    // Warm start: the last impulses carried with the body, p0 = a p_body, whose body-frame
    // product is the one kept. (Extrapolating p0 linearly from the last two solves cuts the
    // sweeps but, at loose tolerances, biases every solve forward: the open-loop walk fell.)
    for (int k = 0; k < n; ++k)
      warm_start[k].noalias() = node_rotation(k) * impulse_.segment<3>(3 * k);
    target.warm_product = product_; // same size: no allocation
  }
  if (has_offset_) {
    for (int k = 0; k < n; ++k)
      offset_contact_.segment<3>(3 * k).noalias() = node_rotation(k) * offset_.segment<3>(3 * k);
  }
  target.rotation = rotation;
  // The kept product is the solver's warm-start product, renewed from scratch after 50 sweeps
  // of incremental updates (round-off).
  target.warm_product_valid = has_last_solve_ && sweeps_since_fresh_ < 50;
  if (!target.warm_product_valid)
    sweeps_since_fresh_ = 0;
}

void PadState::add_rate_terms() {
  const double dt = time_step_, theta = theta_;
  const double theta_dt = theta * dt;
  contact::CompliantPatch& target = block();
  if (damping_ > 0.0) { // U - U_bar = (U - (1-theta) C F_prev) / (beta/dt + theta)
    relaxation_ = (displacement_ - (1.0 - theta) * elastic_) / (damping_ / dt + theta);
    contact::add_deformation_rate_term(target, relaxation_, theta_dt, *problem_);
  } else {
    contact::add_deformation_rate_term(target, displacement_, theta_dt, *problem_);
  }
  if (has_offset_) // -(U_prev - d) / (theta dt)
    problem_->free_velocity.segment(3 * target.first_contact, offset_contact_.size()) +=
        offset_contact_ / theta_dt;
}

void PadState::finish_step(const Eigen::Ref<const Eigen::VectorXd>& impulses,
                           const contact::ContactSolver& solver,
                           const contact::SolverResult& result, Eigen::Vector3d* node_impulses) {
  const double dt = time_step_, theta = theta_;
  const double theta_dt = theta * dt;
  const double lag = (1.0 - theta) * dt;
  const int n = n_nodes();
  // The step's impulse: the last step's force over (1 - theta) dt, then the solve's.
  for (int k = 0; k < n; ++k)
    node_impulses[k].setZero();
  if (has_force_) {
    for (int k = 0; k < n; ++k)
      node_impulses[k] = lag * force_.segment<3>(3 * k);
    force_.setZero();
    has_force_ = false;
  }
  const contact::CompliantPatch& target = block();
  if (target.n_contacts == 0) {
    if (lifted_offset_ && has_offset_)
      displacement_ = offset_contact_;
    return;
  }
  const int first = target.first_contact;
  for (int k = 0; k < n; ++k)
    node_impulses[k] += impulses.segment<3>(3 * (first + k));
  // F = P / (theta dt); U = C F = theta dt (I (x) a) C/(theta dt)^2 (I (x) a)^T P from the
  // solver's product (no pass over C).
  force_ = impulses.segment(3 * first, 3 * n) / theta_dt;
  has_force_ = true;
  product_ = solver.patch_product(target);
  impulse_ = impulses.segment(3 * first, 3 * n);
  contact::rotate_to_patch(target, impulse_);
  has_last_solve_ = true;
  // A direct solve's product is fresh (no incremental updates).
  sweeps_since_fresh_ = result.direct ? 0 : sweeps_since_fresh_ + result.iterations;
  if (damping_ > 0.0)
    relaxation_ = displacement_ - relaxation_; // U_bar (before U is renewed)
  for (int k = 0; k < n; ++k)
    displacement_.segment<3>(3 * k).noalias() =
        theta_dt * (node_rotation(k) * product_.segment<3>(3 * k));
  if (damping_ > 0.0) { // U+ = a C F + U_bar; C F = (a C F) / a for the next step
    const double a = theta / (damping_ / dt + theta);
    elastic_ = displacement_ / a;
    displacement_ += relaxation_;
  }
  if (has_offset_)
    displacement_ += offset_contact_;
}

} // namespace plantar::coupling
