#pragma once
// Foot form "rigid": 8 contact points on each sole's outline (4 corners + 4 edge midpoints of
// Sole/Length x Sole/Width) in the sole frame, or an n x n grid over it (Robot/Rigid foot grid).

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
};

} // namespace plantar::app
