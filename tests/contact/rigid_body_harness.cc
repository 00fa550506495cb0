#include "tests/contact/rigid_body_harness.h"

#include "contact/compliance_terms.h"

#include <Eigen/Cholesky>
#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace plantar::contact::test {

namespace {
Eigen::Matrix3d skew(const Eigen::Vector3d& r) {
  Eigen::Matrix3d s;
  s << 0, -r.z(), r.y(), r.z(), 0, -r.x(), -r.y(), r.x(), 0;
  return s;
}
} // namespace

Eigen::Matrix3d RigidBody::world_inertia() const {
  const Eigen::Matrix3d rot = orientation.toRotationMatrix();
  return rot * principal_inertia.asDiagonal() * rot.transpose();
}

Eigen::Vector3d box_inertia(double mass, const Eigen::Vector3d& size) {
  const Eigen::Vector3d sq = size.cwiseProduct(size);
  return mass / 12.0 * Eigen::Vector3d(sq.y() + sq.z(), sq.x() + sq.z(), sq.x() + sq.y());
}

std::vector<Eigen::Vector3d> box_bottom_grid(const Eigen::Vector3d& size, int n_per_side) {
  std::vector<Eigen::Vector3d> points;
  for (int i = 0; i < n_per_side; ++i)
    for (int j = 0; j < n_per_side; ++j) {
      const double u = n_per_side == 1 ? 0.5 : double(i) / (n_per_side - 1);
      const double w = n_per_side == 1 ? 0.5 : double(j) / (n_per_side - 1);
      points.emplace_back((u - 0.5) * size.x(), (w - 0.5) * size.y(), -0.5 * size.z());
    }
  return points;
}

void RigidWorld::set_patch(const Eigen::MatrixXd& compliance) {
  patch_compliance_ = compliance;
  n_patch_ = static_cast<int>(compliance.rows() / 3);
  patch_displacement_.setZero(3 * n_patch_);
}

void RigidWorld::finalize() {
  const int n = static_cast<int>(contacts.size());
  problem_.resize(n, 6 * static_cast<int>(bodies.size()));
  solver_.resize(n, 6 * static_cast<int>(bodies.size()));
  solver_impulses_.setZero(3 * n);
  contact_impulse_.setZero(3 * n);
  active_.assign(n, 0);
  problem_to_contact_.assign(n, -1);
  jacobian_rows_.setZero(3, 6 * bodies.size());
  problem_.patches.clear();
  if (n_patch_ > 0) {
    CompliantPatch patch;
    patch.first_contact = 0;
    patch.n_contacts = n_patch_;
    patch.compliance_over_dt.setZero(3 * n_patch_, 3 * n_patch_);
    problem_.patches.push_back(patch);
  }
}

Eigen::Matrix3d RigidWorld::frame(int c) const {
  const PointContact& contact = contacts[c];
  Eigen::Matrix3d rows;
  if (contact.body_b < 0) {
    const double c = std::cos(ground_tangent_angle), s = std::sin(ground_tangent_angle);
    rows << 0, 0, 1, c, s, 0, -s, c, 0;
  } else {
    const Eigen::Matrix3d rot = bodies[contact.body_b].orientation.toRotationMatrix();
    rows.row(0) = rot.col(2).transpose();
    rows.row(1) = rot.col(0).transpose();
    rows.row(2) = rot.col(1).transpose();
  }
  return rows;
}

Eigen::Vector3d RigidWorld::world_point(int c) const {
  const RigidBody& body = bodies[contacts[c].body_a];
  return body.position + body.orientation * contacts[c].point;
}

double RigidWorld::gap(int c) const {
  const PointContact& contact = contacts[c];
  const Eigen::Vector3d point = world_point(c);
  double g;
  if (contact.body_b < 0) {
    g = point.z();
  } else {
    const RigidBody& b = bodies[contact.body_b];
    const Eigen::Vector3d origin =
        b.position + b.orientation * Eigen::Vector3d(0, 0, contact.plane_height);
    g = frame(c).row(0).dot(point - origin);
  }
  if (c < n_patch_)
    g += patch_displacement_[3 * c];
  return g;
}

// Rows (n, t1, t2) of the relative-velocity Jacobian, generalized velocity
// ordered (v_b, omega_b) per body.
void RigidWorld::contact_jacobian_rows(int c, Eigen::Ref<Eigen::MatrixXd> rows) const {
  rows.setZero();
  const PointContact& contact = contacts[c];
  const Eigen::Matrix3d f = frame(c);
  const Eigen::Vector3d point = world_point(c);
  const RigidBody& a = bodies[contact.body_a];
  rows.block<3, 3>(0, 6 * contact.body_a) = f;
  rows.block<3, 3>(0, 6 * contact.body_a + 3) = -f * skew(point - a.position);
  if (contact.body_b >= 0) {
    const RigidBody& b = bodies[contact.body_b];
    rows.block<3, 3>(0, 6 * contact.body_b) -= f;
    rows.block<3, 3>(0, 6 * contact.body_b + 3) -= -f * skew(point - b.position);
  }
}

SolverResult RigidWorld::step(double dt) {
  const int n_bodies = static_cast<int>(bodies.size());
  const int n = static_cast<int>(contacts.size());
  // Free velocities.
  Eigen::VectorXd velocity(6 * n_bodies), free_velocity(6 * n_bodies);
  std::vector<Eigen::Matrix3d> inertia(n_bodies), inertia_chol_inv_t(n_bodies);
  for (int b = 0; b < n_bodies; ++b) {
    const RigidBody& body = bodies[b];
    inertia[b] = body.world_inertia();
    const Eigen::Matrix3d l = inertia[b].llt().matrixL();
    inertia_chol_inv_t[b] = l.transpose().inverse(); // L^-T
    velocity.segment<3>(6 * b) = body.linear_velocity;
    velocity.segment<3>(6 * b + 3) = body.angular_velocity;
    free_velocity.segment<3>(6 * b) =
        body.linear_velocity + dt * (gravity + body.force / body.mass);
    const Eigen::Vector3d gyro = body.angular_velocity.cross(inertia[b] * body.angular_velocity);
    free_velocity.segment<3>(6 * b + 3) =
        body.angular_velocity + dt * inertia[b].ldlt().solve(body.torque - gyro);
  }
  // Active set and problem.
  int row = 0;
  Eigen::Matrix<double, 3, Eigen::Dynamic> g_row(3, 6 * n_bodies);
  for (int c = 0; c < n; ++c) {
    contact_jacobian_rows(c, jacobian_rows_);
    const Eigen::Vector3d v_before = jacobian_rows_ * velocity;
    Eigen::Vector3d v_free = jacobian_rows_ * free_velocity;
    const double g = gap(c);
    const bool is_active =
        c < n_patch_ || g + dt * std::min({v_free[0], v_before[0], 0.0}) <= activation_margin;
    active_[c] = is_active;
    if (!is_active) {
      contact_impulse_.segment<3>(3 * c).setZero();
      continue;
    }
    // G rows = J L^-T (per body: translation 1/sqrt(m), rotation L^-T).
    for (int b = 0; b < n_bodies; ++b) {
      g_row.middleCols<3>(6 * b) = jacobian_rows_.middleCols(6 * b, 3) / std::sqrt(bodies[b].mass);
      g_row.middleCols<3>(6 * b + 3) =
          jacobian_rows_.middleCols(6 * b + 3, 3) * inertia_chol_inv_t[b];
    }
    problem_.rigid_factor.middleRows<3>(3 * row) = g_row;
    problem_.free_velocity.segment<3>(3 * row) = v_free;
    problem_.normal_bias[row] = normal_bias(g, v_before[0], dt, bias);
    problem_.friction[row] = contacts[c].friction;
    solver_impulses_.segment<3>(3 * row) = contact_impulse_.segment<3>(3 * c);
    problem_to_contact_[row] = c;
    ++row;
  }
  problem_.n_contacts = row;
  if (n_patch_ > 0) {
    set_patch_compliance(problem_.patches[0], patch_compliance_, dt);
    add_deformation_rate_term(problem_.patches[0], patch_displacement_, dt, problem_);
  }
  SolverResult result;
  result.status = SolverStatus::converged;
  if (row > 0)
    result = solver_.solve(problem_, settings, solver_impulses_);
  // Velocity update v+ = v_free + M^-1 J^T p.
  Eigen::VectorXd generalized_impulse = Eigen::VectorXd::Zero(6 * n_bodies);
  for (int r = 0; r < row; ++r) {
    const int c = problem_to_contact_[r];
    contact_impulse_.segment<3>(3 * c) = solver_impulses_.segment<3>(3 * r);
    contact_jacobian_rows(c, jacobian_rows_);
    generalized_impulse.noalias() +=
        jacobian_rows_.transpose() * solver_impulses_.segment<3>(3 * r);
  }
  if (n_patch_ > 0)
    contact::patch_displacement(problem_.patches[0], solver_impulses_, dt, patch_displacement_);
  for (int b = 0; b < n_bodies; ++b) {
    RigidBody& body = bodies[b];
    body.linear_velocity =
        free_velocity.segment<3>(6 * b) + generalized_impulse.segment<3>(6 * b) / body.mass;
    body.angular_velocity = free_velocity.segment<3>(6 * b + 3) +
                            inertia[b].ldlt().solve(generalized_impulse.segment<3>(6 * b + 3));
    body.position += dt * body.linear_velocity;
    const Eigen::Vector3d rotation = dt * body.angular_velocity;
    const double angle = rotation.norm();
    if (angle > 0.0)
      body.orientation =
          (Eigen::Quaterniond(Eigen::AngleAxisd(angle, rotation / angle)) * body.orientation)
              .normalized();
  }
  return result;
}

} // namespace plantar::contact::test
