#pragma once
// Flat ground z = z0 (the default: z0 = 0, the ground of every scene before terrains).

#include "contact/terrain.h"

namespace plantar::contact {

class FlatTerrain final : public Terrain {
public:
  /// @p level z0, m, finite. Throws std::invalid_argument otherwise.
  explicit FlatTerrain(double level = 0.0);
  double height(double, double) const override { return level_; }
  Eigen::Vector2d gradient(double, double) const override { return Eigen::Vector2d::Zero(); }
  std::optional<double> level_height() const override { return level_; }

private:
  double level_;
};

/// The plane z = 0 (a static instance: the stepper's default ground).
const Terrain& flat_ground();

} // namespace plantar::contact
