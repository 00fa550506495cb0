#pragma once
// Spatial algebra (Featherstone, "Rigid Body Dynamics Algorithms", 2008, ch. 2),
// in the [linear; angular] order used by Pinocchio.
//
//   motion m = [v; w]   (m/s or m/s^2 at the frame origin; rad/s or rad/s^2)
//   force  f = [f; n]   (N; N m about the frame origin)
//
// SE3 X = (R, p) maps coordinates of a child frame c into its parent frame p:
//   x_p = R x_c + p.
// act(): child -> parent, act_inv(): parent -> child, for motions and forces.

#include <Eigen/Core>
#include <Eigen/Geometry>

namespace plantar::multibody {

using Vector6d = Eigen::Matrix<double, 6, 1>;
using Matrix6d = Eigen::Matrix<double, 6, 6>;
/// A joint's motion subspace: 6 x (1..6) columns, stored without heap allocation.
using Matrix6Xmax6 = Eigen::Matrix<double, 6, Eigen::Dynamic, 0, 6, 6>;

/// Skew-symmetric matrix [a]x with [a]x b = a x b.
inline Eigen::Matrix3d skew(const Eigen::Vector3d& a) {
  Eigen::Matrix3d s;
  s << 0.0, -a.z(), a.y(), a.z(), 0.0, -a.x(), -a.y(), a.x(), 0.0;
  return s;
}

/// Rigid transform (R, p): x_parent = R x_child + p. R orthonormal, p in m.
struct SE3 {
  Eigen::Matrix3d rotation = Eigen::Matrix3d::Identity();
  Eigen::Vector3d translation = Eigen::Vector3d::Zero();

  SE3() = default;
  SE3(const Eigen::Matrix3d& r, const Eigen::Vector3d& p) : rotation(r), translation(p) {}
  static SE3 Identity() { return SE3(); }

  /// Composition (this * other): maps other's child frame into this' parent frame.
  SE3 operator*(const SE3& other) const {
    return SE3(rotation * other.rotation, rotation * other.translation + translation);
  }
  SE3 inverse() const { return SE3(rotation.transpose(), -(rotation.transpose() * translation)); }
  /// Point child -> parent.
  Eigen::Vector3d act_point(const Eigen::Vector3d& x) const { return rotation * x + translation; }
  /// Point parent -> child.
  Eigen::Vector3d act_inv_point(const Eigen::Vector3d& x) const {
    return rotation.transpose() * (x - translation);
  }
  /// Motion child -> parent: w' = R w, v' = R v + p x w'.
  Vector6d act_motion(const Vector6d& m) const {
    Vector6d out;
    out.tail<3>().noalias() = rotation * m.tail<3>();
    out.head<3>().noalias() = rotation * m.head<3>();
    out.head<3>() += translation.cross(out.tail<3>());
    return out;
  }
  /// Motion parent -> child: w = R^T w', v = R^T (v' - p x w').
  Vector6d act_inv_motion(const Vector6d& m) const {
    Vector6d out;
    out.tail<3>().noalias() = rotation.transpose() * m.tail<3>();
    out.head<3>().noalias() = rotation.transpose() * (m.head<3>() - translation.cross(m.tail<3>()));
    return out;
  }
  /// Force child -> parent: f' = R f, n' = R n + p x f'.
  Vector6d act_force(const Vector6d& f) const {
    Vector6d out;
    out.head<3>().noalias() = rotation * f.head<3>();
    out.tail<3>().noalias() = rotation * f.tail<3>();
    out.tail<3>() += translation.cross(out.head<3>());
    return out;
  }
  /// Force parent -> child: f = R^T f', n = R^T (n' - p x f').
  Vector6d act_inv_force(const Vector6d& f) const {
    Vector6d out;
    out.head<3>().noalias() = rotation.transpose() * f.head<3>();
    out.tail<3>().noalias() = rotation.transpose() * (f.tail<3>() - translation.cross(f.head<3>()));
    return out;
  }
  /// 6x6 motion transform matrix X (child -> parent), X m == act_motion(m).
  Matrix6d motion_matrix() const {
    Matrix6d x = Matrix6d::Zero();
    x.topLeftCorner<3, 3>() = rotation;
    x.bottomRightCorner<3, 3>() = rotation;
    x.topRightCorner<3, 3>() = skew(translation) * rotation;
    return x;
  }
};

/// Motion cross product v x m (Featherstone's crm): [w x m_v + v x m_w; w x m_w].
inline Vector6d cross_motion(const Vector6d& v, const Vector6d& m) {
  Vector6d out;
  out.head<3>() = v.tail<3>().cross(m.head<3>()) + v.head<3>().cross(m.tail<3>());
  out.tail<3>() = v.tail<3>().cross(m.tail<3>());
  return out;
}

/// Force cross product v x* f (Featherstone's crf): [w x f; w x n + v x f].
inline Vector6d cross_force(const Vector6d& v, const Vector6d& f) {
  Vector6d out;
  out.head<3>() = v.tail<3>().cross(f.head<3>());
  out.tail<3>() = v.tail<3>().cross(f.tail<3>()) + v.head<3>().cross(f.head<3>());
  return out;
}

/// Rigid-body inertia: mass (kg), centre of mass c (m) and rotational inertia about the
/// centre of mass I_c (kg m^2), all in the body frame.
struct Inertia {
  double mass = 0.0;
  Eigen::Vector3d com = Eigen::Vector3d::Zero();
  Eigen::Matrix3d inertia_com = Eigen::Matrix3d::Zero();

  Inertia() = default;
  Inertia(double m, const Eigen::Vector3d& c, const Eigen::Matrix3d& i)
      : mass(m), com(c), inertia_com(i) {}
  static Inertia Zero() { return Inertia(); }

  /// Momentum I m = [m (v + w x c); I_c w + c x m (v + w x c)].
  Vector6d operator*(const Vector6d& motion) const {
    Vector6d out;
    const Eigen::Vector3d w = motion.tail<3>();
    out.head<3>() = mass * (motion.head<3>() + w.cross(com));
    out.tail<3>() = inertia_com * w + com.cross(out.head<3>());
    return out;
  }
  /// 6x6 spatial inertia [[m 1, -m [c]x], [m [c]x, I_c - m [c]x [c]x]].
  Matrix6d matrix() const {
    Matrix6d out;
    const Eigen::Matrix3d cx = skew(com);
    out.topLeftCorner<3, 3>() = mass * Eigen::Matrix3d::Identity();
    out.topRightCorner<3, 3>() = -mass * cx;
    out.bottomLeftCorner<3, 3>() = mass * cx;
    out.bottomRightCorner<3, 3>() = inertia_com - mass * cx * cx;
    return out;
  }
  /// The same inertia expressed in the parent frame of X (X maps this frame into it).
  Inertia transformed(const SE3& x) const {
    return Inertia(mass, x.act_point(com), x.rotation * inertia_com * x.rotation.transpose());
  }
  /// Sum of two inertias in the same frame (parallel-axis theorem).
  Inertia operator+(const Inertia& other) const {
    const double m = mass + other.mass;
    if (m <= 0.0) {
      return Inertia(0.0, Eigen::Vector3d::Zero(), inertia_com + other.inertia_com);
    }
    const Eigen::Vector3d c = (mass * com + other.mass * other.com) / m;
    const Eigen::Vector3d d1 = com - c;
    const Eigen::Vector3d d2 = other.com - c;
    const Eigen::Matrix3d i =
        inertia_com + other.inertia_com +
        mass * (d1.squaredNorm() * Eigen::Matrix3d::Identity() - d1 * d1.transpose()) +
        other.mass * (d2.squaredNorm() * Eigen::Matrix3d::Identity() - d2 * d2.transpose());
    return Inertia(m, c, i);
  }
  Inertia& operator+=(const Inertia& other) { return *this = *this + other; }
};

/// Rotation by angle (rad) about a unit axis.
inline Eigen::Matrix3d axis_rotation(const Eigen::Vector3d& axis, double angle) {
  return Eigen::AngleAxisd(angle, axis).toRotationMatrix();
}

/// SE3 exponential of a twist [v; w] (body frame), the displacement after unit time:
/// R = exp([w]x), p = V(w) v with V = 1 + (1 - cos t)/t^2 [w]x + (t - sin t)/t^3 [w]x^2.
SE3 exp6(const Vector6d& twist);

/// Quaternion (x, y, z, w storage) of exp([w]x).
Eigen::Quaterniond exp3_quaternion(const Eigen::Vector3d& w);

/// SO(3) logarithm, the inverse of exp3: the rotation vector w = theta a (rad) with
/// R = exp([w]x), theta in [0, pi]. Computed from the unit quaternion (w0, v) of R (Shepperd's
/// method, accurate near 0 and near pi) as w = 2 atan2(|v|, |w0|) sign(w0) v / |v|; at theta = pi
/// either of the two opposite vectors is returned. @param rotation orthonormal 3x3.
Eigen::Vector3d log3(const Eigen::Matrix3d& rotation);

/// Inverse of the left Jacobian of SO(3) at w = log3(R): if R(t) = exp([w(t)]x) moves with the
/// angular velocity omega (world axes, dR/dt = [omega]x R), then dw/dt = J_l^-1(w) omega with
///   J_l^-1(w) = 1 - [w]x / 2 + (1/theta^2 - cot(theta/2) / (2 theta)) [w]x^2,  theta = |w|,
/// (the last coefficient by its Taylor series 1/12 + theta^2/720 + ... near 0; finite up to
/// theta = pi, where it is 1/pi^2). J_l^-1(w) w = w.
Eigen::Matrix3d log3_left_jacobian_inverse(const Eigen::Vector3d& w);

} // namespace plantar::multibody
