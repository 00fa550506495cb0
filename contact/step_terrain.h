#pragma once
// A step: the ground rises by H across the straight edge through (x0, y0) whose upper side is
// along the horizontal unit direction d = (cos psi, sin psi). With s = d . ((x, y) - (x0, y0)):
//   h = z0 + H S(s),  S = 0 for s <= -w/2, 1 for s >= w/2, 3 t^2 - 2 t^3 between (t = s/w + 1/2),
//   grad h = H S'(s) d,  S' = 6 t (1 - t) / w:
// a C1 ramp of horizontal width w centred on the edge (largest slope 1.5 H / w at s = 0).
// With w = 0 the edge is a discontinuity: S = 1 for s >= 0 (a point over the edge belongs to the
// upper level), 0 below, and the normal is vertical on both sides (the riser is not a contact
// surface: a point moving horizontally into it jumps onto the upper level's gap).

#include "contact/terrain.h"

namespace plantar::contact {

class StepTerrain final : public Terrain {
public:
  /// @p rise H (m, finite, either sign), @p heading psi of d (rad, finite), @p edge_point
  /// (x0, y0) on the edge and @p level z0 (m, finite), @p width w (m, >= 0, finite). Throws
  /// std::invalid_argument naming the argument, value and range.
  StepTerrain(double rise, double heading, const Eigen::Vector2d& edge_point, double level,
              double width);
  double height(double x, double y) const override;
  Eigen::Vector2d gradient(double x, double y) const override;

private:
  double rise_, level_, width_;
  Eigen::Vector2d direction_, edge_point_;
};

} // namespace plantar::contact
