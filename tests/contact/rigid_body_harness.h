#pragma once
// Test scaffolding: free rigid bodies (6 DoF, world-frame velocities,
// quaternions) with point contacts against the ground plane z = 0 or against
// the top face of another body, stepped with Moreau-Jean:
//   v_free = v + dt M^-1 (f_ext + m g - omega x I omega),
//   v+ = v_free + M^-1 J^T p,  q+ = q + dt v+ (quaternion by the exponential map),
// p from ContactSolver on the ContactProblem built with G = J L^-T (M = L L^T
// per body). Contacts are active when the predicted gap
// gap + dt min(v_n_free, v_n, 0) <= activation_margin.
// One optional compliant patch: contacts [0, n_patch) against the ground,
// always active, with the sole displacement U_c carried between steps
// (compliance_terms.h). Not a library: the articulated stepper is in multibody/.

#include "contact/contact_problem.h"
#include "contact/contact_solver.h"
#include "contact/position_correction.h"

#include <Eigen/Geometry>
#include <vector>

namespace plantar::contact::test {

struct RigidBody {
  double mass = 1.0;                                           ///< kg
  Eigen::Vector3d principal_inertia = Eigen::Vector3d::Ones(); ///< body frame, kg m^2
  Eigen::Vector3d position = Eigen::Vector3d::Zero();          ///< CoM, world, m
  Eigen::Quaterniond orientation = Eigen::Quaterniond::Identity();
  Eigen::Vector3d linear_velocity = Eigen::Vector3d::Zero();  ///< world, m/s
  Eigen::Vector3d angular_velocity = Eigen::Vector3d::Zero(); ///< world, rad/s
  Eigen::Vector3d force = Eigen::Vector3d::Zero();            ///< external, world, at CoM, N
  Eigen::Vector3d torque = Eigen::Vector3d::Zero();           ///< external, world, N m

  Eigen::Matrix3d world_inertia() const;
};

/// A point of body_a (body frame) against the plane z = 0 (body_b = -1) or the
/// plane z_local = plane_height of body_b (normal = body_b's local z).
struct PointContact {
  int body_a = 0;
  int body_b = -1;
  Eigen::Vector3d point = Eigen::Vector3d::Zero();
  double plane_height = 0.0;
  double friction = 0.5;
};

/// Box of size (sx, sy, sz), uniform mass: principal inertia.
Eigen::Vector3d box_inertia(double mass, const Eigen::Vector3d& size);
/// n x n grid of points on the bottom face (z = -sz/2) of a box, corners included.
std::vector<Eigen::Vector3d> box_bottom_grid(const Eigen::Vector3d& size, int n_per_side);

class RigidWorld {
public:
  Eigen::Vector3d gravity = Eigen::Vector3d(0.0, 0.0, -9.81);
  std::vector<RigidBody> bodies;
  std::vector<PointContact> contacts;
  NormalBiasParameters bias;
  /// Contacts are active when gap + dt min(v_n_free, v_n, 0) <= this (m): a
  /// resting contact hovering a little above its support (e.g. the upper of
  /// two stacked boxes, whose relative free velocity is zero) stays active.
  double activation_margin = 1e-7;
  /// Tangent basis of the ground: t1 = (cos a, sin a, 0), t2 = (-sin a, cos a, 0), rad.
  double ground_tangent_angle = 0.0;
  SolverSettings settings;

  /// Compliant patch on contacts [0, n_patch): C (3 n_patch square, m/N) in the
  /// ground frame (n = z, t1 = x, t2 = y).
  void set_patch(const Eigen::MatrixXd& compliance);

  /// Sizes the problem and the solver; call after bodies and contacts are set.
  void finalize();
  /// One Moreau-Jean step; returns the solver result (converged if no contact).
  SolverResult step(double dt);

  /// Signed gap of contact c (rigid part plus the patch's normal displacement).
  double gap(int c) const;
  /// Impulse of contact c in its frame (n, t1, t2) at the last step, N s.
  Eigen::Vector3d impulse(int c) const { return contact_impulse_.segment<3>(3 * c); }
  bool active(int c) const { return active_[c] != 0; }
  const ContactProblem& problem() const { return problem_; }
  ContactSolver& solver() { return solver_; }
  /// Sole node displacement U_c of the patch (3 n_patch), m.
  const Eigen::VectorXd& patch_displacement() const { return patch_displacement_; }
  /// Contact frame rows (n, t1, t2) of contact c, world.
  Eigen::Matrix3d frame(int c) const;
  Eigen::Vector3d world_point(int c) const;

private:
  void contact_jacobian_rows(int c, Eigen::Ref<Eigen::MatrixXd> rows) const;

  ContactProblem problem_;
  ContactSolver solver_;
  Eigen::VectorXd solver_impulses_; // problem order
  Eigen::VectorXd contact_impulse_; // contact order, warm start
  std::vector<int> active_;
  std::vector<int> problem_to_contact_;
  Eigen::MatrixXd patch_compliance_;
  Eigen::VectorXd patch_displacement_;
  Eigen::MatrixXd jacobian_rows_; // 3 x 6 n_bodies scratch
  int n_patch_ = 0;
};

} // namespace plantar::contact::test
