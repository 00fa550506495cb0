#include "apps/rigid_foot.h"

#include "apps/scene.h"
#include "contact/terrain.h"
#include "multibody/kinematics.h"
#include "multibody/stepper.h"

namespace plantar::app {

namespace {
/// Probes per side of the sole's face (validity check).
constexpr int kProbes = 11;

/// An n x n grid over [-a, a] x [-b, b] (z = 0), row i = x index.
Eigen::Matrix3Xd sole_grid(double a, double b, int n) {
  Eigen::Matrix3Xd grid(3, n * n);
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j)
      grid.col(i * n + j) << -a + 2 * a * i / (n - 1), -b + 2 * b * j / (n - 1), 0.0;
  return grid;
}
} // namespace

RigidFoot::RigidFoot(const Scene& scene) {
  const double a = scene.sole.length / 2, b = scene.sole.width / 2;
  const int n = scene.robot.rigid_foot_grid;
  probes_ = sole_grid(a, b, kProbes);
  depth_limit_ = {"rigid_sole_depth",
                  "depth (m) of the rigid sole's face in the ground (deepest of an 11 x 11 grid)",
                  "Robot/Rigid sole depth warning",
                  "Robot/Rigid sole max depth",
                  ValidityLimit::Bound::upper,
                  scene.robot.rigid_sole_depth_warning,
                  scene.robot.rigid_sole_max_depth,
                  "the ground rises between the rigid foot's contact points, which do not see "
                  "it: use Robot/Rigid foot grid = 9 (or finer) or Robot/Foot form = fem sole"};
  if (n == 0) {
    outline_.resize(3, 8);
    outline_ << a, a, a, 0, -a, -a, -a, 0, //
        -b, 0, b, b, b, 0, -b, -b,         //
        0, 0, 0, 0, 0, 0, 0, 0;
    return;
  }
  outline_ = sole_grid(a, b, n);
}

void RigidFoot::add_contacts(double friction) {
  for (int foot = 0; foot < 2; ++foot) {
    const multibody::Frame& frame = model_->frames[sole_frames_[foot]];
    for (int k = 0; k < outline_.cols(); ++k) {
      const Eigen::Vector3d position = frame.placement.act_point(outline_.col(k));
      feet_[foot].push_back(
          {stepper_->add_contact_point(frame.body, position, friction), frame.body, position});
    }
  }
}

void RigidFoot::report(int foot, const multibody::Data& data, double dt, FootReport& out) const {
  out.force.setZero();
  out.moment.setZero();
  out.torque.setZero();
  out.depth = 0;
  for (const Point& c : feet_[foot]) {
    const Eigen::Vector3d p = stepper_->point_impulse(c.index) / dt; // the step's impulse / dt
    const Eigen::Vector3d f = stepper_->point_frame(c.index) * p;    // (n, t1, t2) -> world
    const Eigen::Vector3d x = data.oMi[c.body].act_point(c.position);
    out.force += f;
    out.moment.x() += f.z() * x.x();
    out.moment.y() += f.z() * x.y();
    out.torque += x.cross(f);
    out.depth = std::max(out.depth, -contact::terrain_gap(stepper_->terrain(), x));
  }
}

void RigidFoot::check_validity(const multibody::Data& data, ValidityMonitor& monitor) const {
  const contact::Terrain& terrain = stepper_->terrain();
  if (terrain.level_height())
    return;
  std::array<double, 2> depth{};
  for (int foot = 0; foot < 2; ++foot) {
    const multibody::SE3 sole = multibody::frame_placement(*model_, data, sole_frames_[foot]);
    for (int k = 0; k < probes_.cols(); ++k)
      depth[foot] =
          std::max(depth[foot], -contact::terrain_gap(terrain, sole.act_point(probes_.col(k))));
  }
  const bool left = depth[1] > depth[0];
  monitor.check(depth_limit_, depth[left ? 1 : 0], left ? "left sole" : "right sole");
}

} // namespace plantar::app
