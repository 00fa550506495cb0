#include "multibody/walking/dcm_stabilizer.h"

#include "multibody/walking/support_polygon.h"

#include <algorithm>
#include <stdexcept>

namespace plantar::walking {
namespace {

double clamp(double x, double limit) {
  return std::clamp(x, -limit, limit);
}

} // namespace

DcmStabilizer::DcmStabilizer(const DcmStabilizerParameters& parameters) : parameters_(parameters) {
  const DcmStabilizerParameters& p = parameters;
  if (!(p.omega > 0 && p.dcm_gain >= 0 && p.dcm_integral_gain >= 0 &&
        p.integral_time_constant > 0 && p.foot_damping > 0 && p.foot_time_constant > 0 &&
        p.force_damping > 0 && p.force_time_constant > 0 && p.support_margin >= 0))
    throw std::invalid_argument("DcmStabilizer: omega, time constants and dampings must be > 0, "
                                "gains and the support margin >= 0");
}

Eigen::Vector2d DcmStabilizer::clamped_target(const StabilizerFoot& f, const Eigen::Vector2d& cop,
                                              double margin, Eigen::Vector2d& target) const {
  const DcmStabilizerParameters& p = parameters_;
  const Eigen::Vector3d local =
      f.rotation.transpose() *
      Eigen::Vector3d(cop.x() - f.position.x(), cop.y() - f.position.y(), 0.0);
  if (f.support)
    target = nearest_in_polygon(local.head<2>(), *f.support, p.support_margin + margin);
  else
    target << clamp(local.x(), std::max(p.sole_half_size.x() - margin, 0.0)),
        clamp(local.y(), std::max(p.sole_half_size.y() - margin, 0.0));
  return (f.rotation * Eigen::Vector3d(local.x() - target.x(), local.y() - target.y(), 0.0))
      .head<2>();
}

Eigen::Vector2d DcmStabilizer::cop_excess(const StabilizerFoot& foot, const Eigen::Vector2d& cop,
                                          double margin) const {
  Eigen::Vector2d target;
  return clamped_target(foot, cop, margin, target);
}

void DcmStabilizer::update(const Eigen::Vector2d& dcm, const Eigen::Vector2d& dcm_ref,
                           const Eigen::Vector2d& zmp_ref,
                           const std::array<StabilizerFoot, 2>& feet, double dt) {
  const DcmStabilizerParameters& p = parameters_;
  error_ = dcm - dcm_ref;
  integral_ += dt * (error_ - integral_ / p.integral_time_constant);
  desired_zmp_ = zmp_ref + (1 + p.dcm_gain / p.omega) * error_ + p.dcm_integral_gain * integral_;

  // Distribution.
  std::array<Eigen::Vector2d, 2> cop_target;
  std::array<double, 2> force_target{0, 0};
  const double total = feet[0].force.z() * feet[0].contact + feet[1].force.z() * feet[1].contact;
  const bool both = feet[0].contact && feet[1].contact;
  if (both) {
    const Eigen::Vector2d right = feet[0].position.head<2>(), left = feet[1].position.head<2>();
    const Eigen::Vector2d d = left - right;
    const double s = std::clamp((desired_zmp_ - right).dot(d) / d.squaredNorm(), 0.0, 1.0);
    const Eigen::Vector2d residual = desired_zmp_ - (right + s * d);
    cop_target[0] = right + residual;
    cop_target[1] = left + residual;
    force_target[0] = (1 - s) * total;
    force_target[1] = s * total;
  } else {
    cop_target[0] = cop_target[1] = desired_zmp_;
  }

  // Foot damping control.
  const double roll_damping = p.tilt_damping[0] > 0 ? p.tilt_damping[0] : p.foot_damping;
  const double pitch_damping = p.tilt_damping[1] > 0 ? p.tilt_damping[1] : p.foot_damping;
  zmp_deficit_.setZero();
  for (int foot = 0; foot < 2; ++foot) {
    const StabilizerFoot& f = feet[foot];
    FootOffset& o = offsets_[foot];
    double roll_rate = -o.roll / p.foot_time_constant;
    double pitch_rate = -o.pitch / p.foot_time_constant;
    const double fz = f.force.z();
    if (f.contact && fz > p.min_contact_force) {
      Eigen::Vector2d target;
      const Eigen::Vector2d excess = clamped_target(f, cop_target[foot], 0.0, target);
      const double target_x = target.x(), target_y = target.y();
      if (!both)
        zmp_deficit_ = excess;
      const double cop_x = -f.moment.y() / fz, cop_y = f.moment.x() / fz;
      roll_rate += (cop_y - target_y) * fz / roll_damping;
      pitch_rate += (target_x - cop_x) * fz / pitch_damping;
    }
    o.roll = clamp(o.roll + dt * roll_rate, p.max_foot_rotation);
    o.pitch = clamp(o.pitch + dt * pitch_rate, p.max_foot_rotation);
  }

  // Foot force difference control.
  double rate = -force_offset_ / p.force_time_constant;
  if (both)
    rate += ((force_target[1] - force_target[0]) - (feet[1].force.z() - feet[0].force.z())) /
            p.force_damping;
  force_offset_ = clamp(force_offset_ + dt * rate, p.max_leg_offset);
  offsets_[0].height = 0.5 * force_offset_;
  offsets_[1].height = -0.5 * force_offset_;
}

} // namespace plantar::walking
