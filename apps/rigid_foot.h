#pragma once
// Foot form "rigid": 8 contact points on each sole's outline (4 corners + 4 edge midpoints of
// Sole/Length x Sole/Width) in the sole frame, or an n x n grid over it (Robot/Rigid foot grid).
// Its validity on uneven ground: the ground under the sole between the contact points is not
// seen, so after every step the sole's face is probed on an 11 x 11 grid and its deepest point
// in the ground, max_k max(0, -g(x_k)) (contact/terrain.h's gap, m, the deeper foot), is checked
// against Robot/Rigid sole depth warning and Robot/Rigid sole max depth. On a plane (the
// terrain's level_height) the face's deepest point is a corner, a contact point: no probe.

#include "apps/foot_model.h"

#include <vector>

namespace plantar::app {

struct Scene;

class RigidFoot : public FootModel {
public:
  /// The outline of @p scene's Sole/Length x Sole/Width.
  explicit RigidFoot(const Scene& scene);
  const Eigen::Matrix3Xd& contact_points() const override { return outline_; }
  int max_contacts() const override { return 2 * static_cast<int>(outline_.cols()); }
  void report(int foot, const multibody::Data& data, double dt, FootReport& out) const override;
  /// The deepest probe of the soles' faces in the ground (header comment). No heap allocation.
  void check_validity(const multibody::Data& data, ValidityMonitor& monitor) const override;

protected:
  void add_contacts(double friction) override;

private:
  struct Point {
    int index = -1; ///< stepper point
    int body = 0;
    Eigen::Vector3d position; ///< body coordinates, m
  };
  Eigen::Matrix3Xd outline_; ///< 3 x 8 (or n^2), sole frame, m
  std::array<std::vector<Point>, 2> feet_;
  Eigen::Matrix3Xd probes_; ///< 3 x 121, the 11 x 11 grid over the sole, sole frame, m
  ValidityLimit depth_limit_;
};

} // namespace plantar::app
