// Touchdown adaptation: the swing foot's height reference follows the ground it finds, for
// grounds higher or lower than planned (an unplanned step, rough ground). Per foot, from the
// reference sole's clearance above its planned ground, h_ref(t) = z_ref - ground(t) (m), and the
// F/T sensor's normal force f (N):
//   early touchdown: in the swing's descent (h_ref > down height, decreasing) f > f_td:
//     the ground is higher by the remaining clearance, level <- level + h_ref(t_c), and the foot
//     is held there for the rest of the swing: dz = level - h_ref(t);
//   late touchdown: the plan is down (h_ref <= down height) and no longer descending, and the
//     foot has not touched since its lift-off: the foot searches downwards, level <- level - v_s dt
//     (clamped at -max_offset) until f > f_td;
//   otherwise dz = level: a foot keeps the level it last found (the next swing starts from it).
// A swing starts when the plan lifts the foot (h_ref rises above the down height).
// The offset dz (m, along world z) is added to the foot's reference by the balance loop
// (balance_controller.h). Allocates nothing.
#pragma once

#include <Eigen/Core>

#include <array>

namespace plantar::walking {

struct TouchdownParameters {
  bool enabled = false;         ///< off: dz = 0 always
  double force = 50;            ///< f_td, N, > 0: the F/T normal force that marks a touchdown
  double search_velocity = 0.1; ///< v_s, m/s, > 0: a late foot's downward search speed
  double max_offset = 0.05;     ///< m, > 0: |level| clamp
  /// m, > 0: h_ref at or under it is "planned down" (the swing has ended; a touchdown at
  /// 0.1 m/s covers its last 0.1 mm in 1 ms)
  double down_height = 1e-4;
};

class TouchdownAdaptation {
public:
  explicit TouchdownAdaptation(const TouchdownParameters& parameters = {});
  /// One control period of length @p dt (s): @p clearance h_ref and @p normal_force f of each
  /// foot (right, left). Returns dz of each foot (m).
  const Eigen::Vector2d& update(const Eigen::Vector2d& clearance,
                                const Eigen::Vector2d& normal_force, double dt);
  const Eigen::Vector2d& offsets() const { return offset_; }
  /// The ground level found under each foot, relative to its plan (m).
  const Eigen::Vector2d& levels() const { return level_; }
  /// Early and late touchdowns detected so far (both feet).
  int early_touchdowns() const { return early_; }
  int late_touchdowns() const { return late_; }

private:
  TouchdownParameters parameters_;
  Eigen::Vector2d offset_ = Eigen::Vector2d::Zero(), level_ = Eigen::Vector2d::Zero();
  Eigen::Vector2d previous_clearance_ = Eigen::Vector2d::Zero();
  std::array<bool, 2> touched_{true, true}; ///< touched the ground since the last lift-off
  std::array<bool, 2> searching_{false, false};
  bool first_ = true;
  int early_ = 0, late_ = 0;
};

} // namespace plantar::walking
