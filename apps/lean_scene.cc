#include "apps/scene_reference.h"

#include <cmath>

namespace plantar::app {

SceneReference lean_scene_reference(const SceneReferenceInputs& in) {
  const LeanSceneParameters& parameters = in.scene.lean;
  const walking::WalkingParameters& walk = in.scene.walking.walk;
  walking::LeanParameters lean;
  lean.final_angle = parameters.final_angle_deg * M_PI / 180.0;
  lean.start_time = parameters.start_time;
  lean.ramp_time = parameters.ramp_time;
  lean.hold_time = parameters.hold_time;
  SceneReference out;
  out.duration = in.scene.simulation.duration;
  out.reference = walking::make_lean_reference(in.reference_model, in.reference_humanoid, lean,
                                               walk.initial_right, walk.initial_left, in.posture);
  return out;
}

} // namespace plantar::app
