#include "apps/rigid_foot.h"

#include "apps/scene.h"
#include "contact/terrain.h"
#include "multibody/stepper.h"

namespace plantar::app {

RigidFoot::RigidFoot(const Scene& scene) {
  const double a = scene.sole.length / 2, b = scene.sole.width / 2;
  const int n = scene.robot.rigid_foot_grid;
  if (n == 0) {
    outline_.resize(3, 8);
    outline_ << a, a, a, 0, -a, -a, -a, 0, //
        -b, 0, b, b, b, 0, -b, -b,         //
        0, 0, 0, 0, 0, 0, 0, 0;
    return;
  }
  outline_.resize(3, n * n);
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j)
      outline_.col(i * n + j) << -a + 2 * a * i / (n - 1), -b + 2 * b * j / (n - 1), 0.0;
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

} // namespace plantar::app
