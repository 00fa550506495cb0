#include "multibody/walking/joint_reference.h"

#include <algorithm>
#include <cmath>
#include <fstream>
#include <stdexcept>

namespace plantar::walking {

void JointReference::sample(double t, Eigen::Ref<Eigen::VectorXd> q_out,
                            Eigen::Isometry3d& base_out) const {
  const int n = n_samples();
  if (n == 0)
    throw std::runtime_error("JointReference::sample: empty reference");
  if (q_out.size() != q.cols())
    throw std::invalid_argument("JointReference::sample: q_out has " +
                                std::to_string(q_out.size()) + " entries, the reference " +
                                std::to_string(q.cols()) + " joints");
  int k, k1;
  double w;
  interval(t, k, k1, w);
  // Cubic Hermite basis; tangents (per sample) by central differences, one-sided at the ends.
  const double h00 = (2 * w - 3) * w * w + 1, h10 = ((w - 2) * w + 1) * w;
  const double h01 = (3 - 2 * w) * w * w, h11 = (w - 1) * w * w;
  const int km = std::max(k - 1, 0), k2 = std::min(k1 + 1, n - 1);
  const double sk = k1 > km ? 1.0 / (k1 - km) : 0.0, sk1 = k2 > k ? 1.0 / (k2 - k) : 0.0;
  q_out = (h00 * q.row(k) + h01 * q.row(k1) + (h10 * sk) * (q.row(k1) - q.row(km)) +
           (h11 * sk1) * (q.row(k2) - q.row(k)))
              .transpose();
  const Eigen::Quaterniond q0(base_orientation(k, 0), base_orientation(k, 1),
                              base_orientation(k, 2), base_orientation(k, 3));
  const Eigen::Quaterniond q1(base_orientation(k1, 0), base_orientation(k1, 1),
                              base_orientation(k1, 2), base_orientation(k1, 3));
  base_out.setIdentity();
  base_out.linear() = q0.slerp(w, q1).toRotationMatrix();
  base_out.translation() = (h00 * base_position.row(k) + h01 * base_position.row(k1) +
                            (h10 * sk) * (base_position.row(k1) - base_position.row(km)) +
                            (h11 * sk1) * (base_position.row(k2) - base_position.row(k)))
                               .transpose();
}

void JointReference::interval(double t, int& k, int& k1, double& w) const {
  const int n = n_samples();
  t = std::clamp(t, 0.0, duration());
  k = std::min(static_cast<int>(std::floor(t / period)), n - 1);
  k1 = std::min(k + 1, n - 1);
  w = k1 == k ? 0.0 : std::clamp((t - time(k)) / period, 0.0, 1.0);
}

void JointReference::resize(int n, double sample_period, const std::vector<std::string>& names) {
  joint_names = names;
  period = sample_period;
  time.resize(n);
  for (int k = 0; k < n; ++k)
    time(k) = k * period;
  q.resize(n, static_cast<Eigen::Index>(names.size()));
  base_position.resize(n, 3);
  base_orientation.resize(n, 4);
  com.resize(n, 3);
  ground.setZero(n, 2);
}

Eigen::Vector2d JointReference::ground_at(double t) const {
  if (ground.rows() != n_samples())
    return Eigen::Vector2d::Zero();
  int k, k1;
  double w;
  interval(t, k, k1, w);
  return ((1 - w) * ground.row(k) + w * ground.row(k1)).transpose();
}

const Eigen::Matrix2Xd* JointReference::support_at(int foot, double t) const {
  if (support_index.rows() != n_samples() || n_samples() == 0)
    return nullptr;
  int k, k1;
  double w;
  interval(t, k, k1, w);
  const Eigen::Matrix2Xd& polygon = supports[support_index(w < 0.5 ? k : k1, foot)];
  return polygon.cols() >= 3 ? &polygon : nullptr;
}

Eigen::Vector2d JointReference::swing_at(int foot, double t) const {
  if (swing_progress.rows() != n_samples() || n_samples() == 0)
    return Eigen::Vector2d(-1, -1);
  int k, k1;
  double w;
  interval(t, k, k1, w);
  const int nearer = w < 0.5 ? k : k1;
  if (swing_progress(nearer, foot) < 0)
    return Eigen::Vector2d(-1, -1);
  // A down neighbour: before the swing (k) its start, after it (k1) its end.
  const double a = swing_progress(k, foot) < 0 ? 0.0 : swing_progress(k, foot);
  const double b = swing_progress(k1, foot) < 0 ? 1.0 : swing_progress(k1, foot);
  return Eigen::Vector2d((1 - w) * a + w * b, swing_end(nearer, foot));
}

void JointReference::set(int k, const Eigen::Isometry3d& base,
                         const Eigen::Ref<const Eigen::VectorXd>& angles,
                         const Eigen::Vector3d& centre_of_mass) {
  q.row(k) = angles.transpose();
  base_position.row(k) = base.translation().transpose();
  const Eigen::Quaterniond quat(base.linear());
  base_orientation.row(k) << quat.w(), quat.x(), quat.y(), quat.z();
  com.row(k) = centre_of_mass.transpose();
}

void JointReference::write_csv(const std::string& path) const {
  std::ofstream out(path);
  if (!out)
    throw std::runtime_error("JointReference::write_csv: cannot open '" + path + "' for writing");
  out << "t,base_x,base_y,base_z,base_qw,base_qx,base_qy,base_qz,com_x,com_y,com_z";
  for (const std::string& name : joint_names)
    out << "," << name;
  out << "\n";
  out.precision(17);
  for (int k = 0; k < n_samples(); ++k) {
    out << time(k);
    for (int i = 0; i < 3; ++i)
      out << "," << base_position(k, i);
    for (int i = 0; i < 4; ++i)
      out << "," << base_orientation(k, i);
    for (int i = 0; i < 3; ++i)
      out << "," << com(k, i);
    for (Eigen::Index j = 0; j < q.cols(); ++j)
      out << "," << q(k, j);
    out << "\n";
  }
  if (!out)
    throw std::runtime_error("JointReference::write_csv: error while writing '" + path + "'");
}

} // namespace plantar::walking
