#include "apps/scene_reference.h"

namespace plantar::app {

SceneReference walk_scene_reference(const SceneReferenceInputs& in) {
  walking::PreviewControlParameters preview;
  preview.period = in.scene.walking.walk.period;
  preview.preview_time = in.scene.walking.preview_time;
  // The ZMP is on the ground, the feet's lift (a FEM sole's thickness) below the sole frames.
  walking::WalkingParameters lifted = in.scene.walking.walk;
  lifted.ground_clearance = in.lift;
  SceneReference out;
  out.duration = in.scene.simulation.duration;
  out.reference = walking::make_walking_pattern(in.reference_model, in.reference_humanoid, lifted,
                                                preview, in.posture)
                      .reference;
  return out;
}

} // namespace plantar::app
