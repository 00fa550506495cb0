#include "apps/scene_reference.h"
#include "multibody/walking/terrain_footsteps.h"

namespace plantar::app {

SceneReference walk_scene_reference(const SceneReferenceInputs& in) {
  walking::PreviewControlParameters preview;
  preview.period = in.scene.walking.walk.period;
  preview.preview_time = in.scene.walking.preview_time;
  // The ZMP is on the ground, the feet's lift (a FEM sole's thickness) below the sole frames.
  walking::WalkingParameters lifted = in.scene.walking.walk;
  lifted.ground_clearance = in.lift;
  if (in.scene.walking.placement == FootstepPlacement::terrain) {
    // The sole rests on its contact points (a rigid foot's outline, a sole's nodes), or on a
    // grid over its outline when they are many (the placement is O(n^4)).
    const Eigen::Matrix3Xd& points = in.feet.contact_points();
    const int samples = in.scene.walking.footprint_samples;
    const walking::SolePoints sole =
        points.cols() >= 3 && points.cols() <= samples * samples
            ? walking::SolePoints(points.topRows<2>())
            : walking::sole_grid(in.scene.sole.length, in.scene.sole.width, samples);
    walking::place_walk_on_terrain(in.terrain, sole, in.scene.walking.zmp_margin, lifted,
                                   in.scene.walking.foothold);
  }
  SceneReference out;
  out.duration = in.scene.simulation.duration;
  out.reference = walking::make_walking_pattern(in.reference_model, in.reference_humanoid, lifted,
                                                preview, in.posture)
                      .reference;
  return out;
}

} // namespace plantar::app
