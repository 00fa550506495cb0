#include "multibody/walking/footstep_plan.h"

#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>
#include <sstream>
#include <stdexcept>

namespace plantar::walking {
namespace {

void require(bool ok, const char* name, double value, const char* range) {
  if (!ok || !std::isfinite(value)) {
    std::ostringstream msg;
    msg << "WalkingParameters." << name << " = " << value << " is outside " << range;
    throw std::invalid_argument(msg.str());
  }
}

} // namespace

void check_walking_parameters(const WalkingParameters& p) {
  require(p.period > 0.0 && p.period <= 0.1, "period", p.period, "(0, 0.1] s");
  require(p.single_support_time >= 2 * p.period, "single_support_time", p.single_support_time,
          "[2 period, inf) s");
  require(p.double_support_time >= p.period, "double_support_time", p.double_support_time,
          "[period, inf) s");
  require(p.initial_double_support_time >= p.period, "initial_double_support_time",
          p.initial_double_support_time, "[period, inf) s");
  require(p.final_double_support_time >= p.period, "final_double_support_time",
          p.final_double_support_time, "[period, inf) s");
  require(p.standing_before >= 0.0, "standing_before", p.standing_before, "[0, inf) s");
  require(p.standing_after >= 0.0, "standing_after", p.standing_after, "[0, inf) s");
  require(p.step_height >= 0.0 && p.step_height <= 0.3, "step_height", p.step_height, "[0, 0.3] m");
  require(p.touchdown_velocity >= 0.0 && p.touchdown_velocity <= 1.0, "touchdown_velocity",
          p.touchdown_velocity, "[0, 1] m/s");
  if (p.touchdown_velocity * p.single_support_time > 19.0 * p.step_height) {
    std::ostringstream msg;
    msg << "WalkingParameters.touchdown_velocity = " << p.touchdown_velocity
        << " m/s is outside [0, 19 step_height / single_support_time] = [0, "
        << 19.0 * p.step_height / p.single_support_time
        << "] m/s: a faster touchdown raises the swing foot above step_height = " << p.step_height
        << " m";
    throw std::invalid_argument(msg.str());
  }
  require(p.ground_clearance >= 0.0 && p.ground_clearance <= 0.1, "ground_clearance",
          p.ground_clearance, "[0, 0.1] m");
  require(p.min_lift_fraction >= 0.0 && p.min_lift_fraction <= 0.45, "min_lift_fraction",
          p.min_lift_fraction, "[0, 0.45]");
  require(p.swing_ground_margin >= 0.0 && p.swing_ground_margin <= 0.05, "swing_ground_margin",
          p.swing_ground_margin, "[0, 0.05] m");
  for (const Footstep& f : p.footsteps)
    require(f.lift_fraction >= 0.0 && f.lift_fraction <= 0.45, "footstep lift_fraction",
            f.lift_fraction, "[0, 0.45]");
  require(p.max_step_length > 0.0, "max_step_length", p.max_step_length, "(0, inf) m");
  Footstep right = p.initial_right, left = p.initial_left;
  for (size_t i = 0; i < p.footsteps.size(); ++i) {
    const Footstep& f = p.footsteps[i];
    if (!std::isfinite(f.x) || !std::isfinite(f.y) || !std::isfinite(f.yaw) ||
        !std::isfinite(f.z) || !(std::abs(f.roll) < 0.5 * M_PI) ||
        !(std::abs(f.pitch) < 0.5 * M_PI))
      throw std::invalid_argument("WalkingParameters.footsteps[" + std::to_string(i) +
                                  "] is not finite or tilted by pi/2 or more");
    Footstep& swing = (i % 2 == 0) == p.right_foot_first ? right : left;
    const double length = std::hypot(f.x - swing.x, f.y - swing.y);
    if (length > p.max_step_length) {
      std::ostringstream msg;
      msg << "WalkingParameters.footsteps[" << i << "]: step length " << length
          << " m exceeds max_step_length = " << p.max_step_length << " m";
      throw std::invalid_argument(msg.str());
    }
    swing = f;
  }
}

Eigen::Matrix3d footstep_rotation(double yaw, double pitch, double roll) {
  const Eigen::Matrix3d heading =
      Eigen::AngleAxisd(yaw, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  if (pitch == 0.0 && roll == 0.0)
    return heading; // level ground: the same bits as before tilts existed
  return heading * Eigen::AngleAxisd(pitch, Eigen::Vector3d::UnitY()).toRotationMatrix() *
         Eigen::AngleAxisd(roll, Eigen::Vector3d::UnitX()).toRotationMatrix();
}

Eigen::Vector2d zmp_target(const Footstep& f) {
  if (f.zmp_x == 0.0 && f.zmp_y == 0.0)
    return Eigen::Vector2d(f.x, f.y); // the sole centre: the same bits as before ZMP targets
  return Eigen::Vector2d(f.x, f.y) +
         (footstep_rotation(f.yaw, f.pitch, f.roll) * Eigen::Vector3d(f.zmp_x, f.zmp_y, 0.0))
             .head<2>();
}

Eigen::Vector3d quintic_transition(double tau) {
  tau = std::clamp(tau, 0.0, 1.0);
  const double t2 = tau * tau, t3 = t2 * tau;
  return Eigen::Vector3d(t3 * (10.0 - 15.0 * tau + 6.0 * t2), 30.0 * t2 * (1.0 - tau) * (1.0 - tau),
                         60.0 * tau * (1.0 - tau) * (1.0 - 2.0 * tau));
}

Eigen::Vector3d swing_height_profile(double tau) {
  tau = std::clamp(tau, 0.0, 1.0);
  const double a = tau * (1.0 - tau);
  // h = 64 a^3, a' = 1 - 2 tau, a'' = -2.
  const double da = 1.0 - 2.0 * tau;
  return Eigen::Vector3d(64.0 * a * a * a, 192.0 * a * a * da,
                         64.0 * (6.0 * a * da * da - 6.0 * a * a));
}

Eigen::Vector3d touchdown_profile(double tau) {
  tau = std::clamp(tau, 0.0, 1.0);
  // g = r (1 - tau), r = tau^3 (2 tau - 1)^2 = 4 tau^5 - 4 tau^4 + tau^3.
  const double t2 = tau * tau, t3 = t2 * tau;
  const double r = t3 * (2.0 * tau - 1.0) * (2.0 * tau - 1.0);
  const double dr = 20.0 * t2 * t2 - 16.0 * t3 + 3.0 * t2;
  const double d2r = 80.0 * t3 - 48.0 * t2 + 6.0 * tau;
  return Eigen::Vector3d(r * (1.0 - tau), dr * (1.0 - tau) - r, d2r * (1.0 - tau) - 2.0 * dr);
}

Eigen::Vector3d swing_foot_height(const WalkingParameters& p, double tau) {
  const double T = p.single_support_time;
  const Eigen::Vector3d z =
      p.step_height * swing_height_profile(tau) + p.touchdown_velocity * T * touchdown_profile(tau);
  return Eigen::Vector3d(z(0), z(1) / T, z(2) / (T * T));
}

SwingSample swing_sample(const WalkingParameters& p, const Footstep& from, const Footstep& to,
                         double tau) {
  const double f = std::max(to.lift_fraction, p.min_lift_fraction);
  SwingSample out;
  const double s = out.progress = quintic_transition((tau - f) / (1.0 - 2.0 * f))(0);
  out.sole.x = from.x + s * (to.x - from.x);
  out.sole.y = from.y + s * (to.y - from.y);
  out.sole.yaw = from.yaw + s * std::remainder(to.yaw - from.yaw, 2 * M_PI);
  out.sole.roll = from.roll + s * (to.roll - from.roll);
  out.sole.pitch = from.pitch + s * (to.pitch - from.pitch);
  out.ground = from.z + s * (to.z - from.z);
  out.sole.z = out.ground + swing_foot_height(p, tau)(0);
  return out;
}

FootstepPlan make_footstep_plan(const WalkingParameters& p) {
  check_walking_parameters(p);
  const double T = p.period;
  const int n_steps = static_cast<int>(p.footsteps.size());
  const double walk_time =
      p.initial_double_support_time + n_steps * (p.single_support_time + p.double_support_time) -
      (n_steps > 0 ? p.double_support_time : 0.0) + p.final_double_support_time;
  const double total = p.standing_before + walk_time + p.standing_after;
  FootstepPlan plan;
  plan.n_samples = static_cast<int>(std::floor(total / T + 1e-9)) + 1;
  plan.walk_start = p.standing_before;
  plan.walk_end = p.standing_before + walk_time;
  const int n = plan.n_samples;
  plan.time.resize(n);
  plan.zmp_reference.resize(n, 2);
  plan.right_sole.resize(n, 3);
  plan.left_sole.resize(n, 3);
  plan.right_yaw.resize(n);
  plan.left_yaw.resize(n);
  plan.right_tilt.resize(n, 2);
  plan.left_tilt.resize(n, 2);
  plan.ground.resize(n, 2);
  plan.supports.clear();
  plan.supports.push_back(p.initial_right.support);
  plan.supports.push_back(p.initial_left.support);
  for (const Footstep& f : p.footsteps)
    plan.supports.push_back(f.support);
  plan.support_index.resize(n, 2);
  plan.phase.assign(n, SupportPhase::double_support);
  plan.swing_progress.setConstant(n, 2, -1.0);
  plan.swing_end.setConstant(n, 2, -1.0);

  // Event list: each step i: single support [ss_start_i, ss_start_i + Tss], then double
  // support Tds (except after the last step, where the final double support follows).
  std::vector<double> ss_start(n_steps);
  double t = p.standing_before + p.initial_double_support_time;
  for (int i = 0; i < n_steps; ++i) {
    ss_start[i] = t;
    t += p.single_support_time + p.double_support_time;
  }
  // Stores sample k: a foot at rest on its placement f, or (swing) the placement and motion.
  auto store = [&plan](int k, int foot, const Footstep& f, double z, double ground) {
    Eigen::MatrixX3d& sole = foot == 0 ? plan.right_sole : plan.left_sole;
    sole.row(k) << f.x, f.y, z;
    (foot == 0 ? plan.right_yaw : plan.left_yaw)(k) = f.yaw;
    (foot == 0 ? plan.right_tilt : plan.left_tilt).row(k) << f.roll, f.pitch;
    plan.ground(k, foot) = ground;
  };
  for (int k = 0; k < n; ++k) {
    const double time = k * T;
    plan.time(k) = time;
    Footstep right = p.initial_right, left = p.initial_left;
    Eigen::Vector2i on = {0, 1}; // the placements the soles are on
    Eigen::Vector2d zmp;
    bool done = false;
    Eigen::Vector2d previous_support = 0.5 * (zmp_target(right) + zmp_target(left));
    for (int i = 0; i < n_steps && !done; ++i) {
      const bool right_swings = (i % 2 == 0) == p.right_foot_first;
      Footstep& swing = right_swings ? right : left;
      const Footstep& support = right_swings ? left : right;
      const Eigen::Vector2d support_centre = zmp_target(support);
      const double transfer_start =
          i == 0 ? p.standing_before : ss_start[i] - p.double_support_time;
      if (time < ss_start[i]) { // double support before step i: ZMP moves to the support sole
        const double s = (time - transfer_start) / (ss_start[i] - transfer_start);
        zmp = previous_support + std::clamp(s, 0.0, 1.0) * (support_centre - previous_support);
        done = true;
        break;
      }
      const double ss_end = ss_start[i] + p.single_support_time;
      const Footstep& target = p.footsteps[i];
      if (time < ss_end) { // single support: swing foot in the air
        const double tau = (time - ss_start[i]) / p.single_support_time;
        const SwingSample moving = swing_sample(p, swing, target, tau);
        store(k, right_swings ? 0 : 1, moving.sole, moving.sole.z, moving.ground);
        store(k, right_swings ? 1 : 0, support, support.z, support.z);
        plan.phase[k] = right_swings ? SupportPhase::left_support : SupportPhase::right_support;
        plan.zmp_reference.row(k) = support_centre.transpose();
        plan.support_index.row(k) = on.transpose();
        plan.support_index(k, right_swings ? 0 : 1) = 2 + i;
        plan.swing_progress(k, right_swings ? 0 : 1) = moving.progress;
        plan.swing_end(k, right_swings ? 0 : 1) = ss_end;
        done = true;
        break;
      }
      swing = target; // landed
      on[right_swings ? 0 : 1] = 2 + i;
      previous_support = support_centre;
    }
    if (done && plan.phase[k] != SupportPhase::double_support)
      continue;
    if (!done) { // after the last step: final double support back to the feet centre
      const Eigen::Vector2d centre = 0.5 * (zmp_target(right) + zmp_target(left));
      const double start = n_steps > 0 ? ss_start[n_steps - 1] + p.single_support_time
                                       : p.standing_before + p.initial_double_support_time;
      const double s = (time - start) / p.final_double_support_time;
      zmp = previous_support + std::clamp(s, 0.0, 1.0) * (centre - previous_support);
      if (n_steps == 0)
        zmp = centre;
    }
    store(k, 0, right, right.z, right.z);
    store(k, 1, left, left.z, left.z);
    plan.support_index.row(k) = on.transpose();
    plan.zmp_reference.row(k) = zmp.transpose();
  }
  return plan;
}

} // namespace plantar::walking
