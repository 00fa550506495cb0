#include "apps/scene_reference.h"

namespace plantar::app {

SceneReference stand_scene_reference(const SceneReferenceInputs& in) {
  const SimulationParameters& sim = in.scene.simulation;
  const walking::WalkingParameters& walk = in.scene.walking.walk;
  SceneReference out;
  out.duration = sim.duration > 0 ? sim.duration : sim.settle_time + 5.0;
  out.settle_time = sim.settle_time;
  out.reference =
      walking::make_standing_reference(in.reference_model, in.reference_humanoid, out.duration,
                                       walk.initial_right, walk.initial_left, in.posture);
  return out;
}

} // namespace plantar::app
