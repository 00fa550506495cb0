#include "apps/scene_reference.h"

#include "multibody/data.h"
#include "multibody/kinematics.h"

#include <Eigen/Geometry>

#include <algorithm>
#include <stdexcept>

namespace plantar::app {

SceneReference drop_scene_reference(const SceneReferenceInputs& in) {
  const SimulationParameters& sim = in.scene.simulation;
  const walking::Humanoid& humanoid = in.humanoid;
  const std::vector<std::string>& names = humanoid.joint_names;
  // Straight legs (all leg joints 0), the posture elsewhere, then Simulation/Drop posture;
  // waist upright above the origin at the height that puts the lowest contact point (feet
  // and pads, undeformed) on z = 0.
  Eigen::VectorXd angles = humanoid.posture;
  for (const auto& leg : humanoid.leg_columns)
    for (int column : leg)
      angles[column] = 0.0;
  for (const auto& [joint, angle] : sim.drop_posture) {
    const auto found = std::find(names.begin(), names.end(), joint);
    if (found == names.end())
      throw std::invalid_argument("Simulation/Drop posture: '" + joint +
                                  "' is not a controlled joint (Robot/Controlled joints)");
    angles[found - names.begin()] = angle;
  }
  Eigen::VectorXd q0 = in.model.neutral_configuration();
  humanoid.to_configuration(in.model, angles, q0);
  multibody::Data data(in.model);
  multibody::forward_kinematics(in.model, data, q0);
  // The least height above the ground over the feet's and the pads' contact points.
  double lowest = in.pads.lowest_point(data, in.terrain);
  for (int foot = 0; foot < 2; ++foot) {
    const multibody::SE3 sole =
        multibody::frame_placement(in.model, data, humanoid.sole_frames[foot]);
    const Eigen::Matrix3Xd& points = in.feet.contact_points();
    for (Eigen::Index k = 0; k < points.cols(); ++k) {
      const Eigen::Vector3d p = sole.act_point(points.col(k));
      lowest = std::min(lowest, p.z() - in.terrain.height(p.x(), p.y()));
    }
  }
  Eigen::Isometry3d base = Eigen::Isometry3d::Identity();
  base.translation() << 0, 0, -lowest - in.lift; // the feet's lift is added back by the loop
  SceneReference out;
  out.duration = sim.duration > 0 ? sim.duration : 1.0;
  out.initial_lift = sim.release_height; // only the initial state: the base is not actuated
  out.reference.resize(2, out.duration, names);
  out.reference.set(0, base, angles, Eigen::Vector3d::Zero());
  out.reference.set(1, base, angles, Eigen::Vector3d::Zero());
  return out;
}

} // namespace plantar::app
