#include "multibody/walking/touchdown_adaptation.h"

#include <algorithm>
#include <stdexcept>
#include <string>

namespace plantar::walking {

TouchdownAdaptation::TouchdownAdaptation(const TouchdownParameters& p) : parameters_(p) {
  if (!(p.force > 0) || !(p.search_velocity > 0) || !(p.max_offset > 0) || !(p.down_height > 0))
    throw std::invalid_argument("TouchdownParameters: force = " + std::to_string(p.force) +
                                " N, search_velocity = " + std::to_string(p.search_velocity) +
                                " m/s, max_offset = " + std::to_string(p.max_offset) +
                                " m and down_height = " + std::to_string(p.down_height) +
                                " m must be > 0");
}

const Eigen::Vector2d& TouchdownAdaptation::update(const Eigen::Vector2d& clearance,
                                                   const Eigen::Vector2d& normal_force, double dt) {
  if (!parameters_.enabled)
    return offset_;
  if (first_) {
    previous_clearance_ = clearance;
    first_ = false;
  }
  for (int foot = 0; foot < 2; ++foot) {
    const double h = clearance[foot];
    const bool loaded = normal_force[foot] > parameters_.force;
    const bool planned_down = h <= parameters_.down_height;
    if (!planned_down && previous_clearance_[foot] <= parameters_.down_height)
      touched_[foot] = false; // the plan lifts the foot off: a swing starts
    double dz = level_[foot];
    if (!planned_down && !touched_[foot]) { // in the air, by the plan
      if (loaded && h < previous_clearance_[foot]) {
        level_[foot] =
            std::clamp(level_[foot] + h, -parameters_.max_offset, parameters_.max_offset);
        touched_[foot] = true;
        ++early_;
      }
      dz = touched_[foot] ? level_[foot] - h : level_[foot];
    } else if (planned_down && !touched_[foot] && h >= previous_clearance_[foot]) {
      // The plan is down and has stopped: late, search downwards.
      if (loaded) {
        touched_[foot] = true;
        if (searching_[foot])
          ++late_;
        searching_[foot] = false;
      } else {
        searching_[foot] = true;
        level_[foot] =
            std::max(level_[foot] - parameters_.search_velocity * dt, -parameters_.max_offset);
      }
      dz = level_[foot];
    } else if (touched_[foot] && !planned_down) {
      dz = level_[foot] - h; // touched down early: held there until the plan is down
    }
    offset_[foot] = dz;
    previous_clearance_[foot] = h;
  }
  return offset_;
}

} // namespace plantar::walking
