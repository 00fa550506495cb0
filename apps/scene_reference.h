#pragma once
// What a humanoid scene type (stand, drop, lean, walk) gives the time loop
// (apps/humanoid_simulation.h): its joint reference and timing. One file per scene type
// (stand_scene.cc, drop_scene.cc, lean_scene.cc, walk_scene.cc); make_scene_reference
// (scene_reference_registry.cc) picks the one of Scene type. A new scene type is a SceneType
// value with its name (apps/scene.cc), a file defining its function, and its row in the
// registry.

#include "apps/foot_model.h"
#include "apps/pad_set.h"
#include "apps/scene.h"
#include "contact/terrain.h"
#include "multibody/model.h"
#include "multibody/walking/humanoid.h"
#include "multibody/walking/joint_reference.h"
#include "multibody/walking/walking_reference.h"

namespace plantar::app {

/// A scene type's reference and timing.
struct SceneReference {
  /// Joint angles and base placement over time, on the robot without the feet's own joints;
  /// the base at the height that puts the (rigid) soles on z = 0.
  walking::JointReference reference;
  double duration = 0;     ///< simulated time (s); 0: reference.duration()
  double initial_lift = 0; ///< m, added to the initial state only (drop: the release height)
  double settle_time = 0;  ///< s, stand: time before the 1 mm window is measured; else 0
};

/// What a scene type's reference may use.
struct SceneReferenceInputs {
  const Scene& scene;
  const multibody::Model& model;               ///< the simulated robot (with the feet's joints)
  const walking::Humanoid& humanoid;           ///< resolved on model
  const multibody::Model& reference_model;     ///< the robot without the feet's joints
  const walking::Humanoid& reference_humanoid; ///< resolved on reference_model
  const FootModel& feet;
  const PadSet& pads;              ///< resolved on model
  const contact::Terrain& terrain; ///< the scene's ground
  double lift = 0;                 ///< m, what the feet add under the sole frames (FootModel::lift)
  walking::PostureParameters posture; ///< CoM height and leg IK of the scene
};

/// Standing still: Simulation/Duration (0: settle time + 5 s), the settle time.
SceneReference stand_scene_reference(const SceneReferenceInputs& in);
/// Released above the ground: straight legs or Simulation/Drop posture held, the lowest contact
/// point (feet and pads) Simulation/Release height above the ground; 1 s by default.
SceneReference drop_scene_reference(const SceneReferenceInputs& in);
/// The waist roll ramp of subsection Lean.
SceneReference lean_scene_reference(const SceneReferenceInputs& in);
/// The walk of subsection Walking (ZMP preview control), the ZMP on the ground below the feet.
SceneReference walk_scene_reference(const SceneReferenceInputs& in);

/// The reference of @p in.scene's type. Throws std::invalid_argument for a scene type that is
/// not a humanoid scene.
SceneReference make_scene_reference(const SceneReferenceInputs& in);

} // namespace plantar::app
