#include "apps/scene_reference.h"

#include <stdexcept>
#include <utility>
#include <vector>

namespace plantar::app {
namespace {

using Factory = SceneReference (*)(const SceneReferenceInputs&);

/// The humanoid scene types and their references.
const std::vector<std::pair<SceneType, Factory>> scene_references{
    {SceneType::stand, stand_scene_reference},
    {SceneType::drop, drop_scene_reference},
    {SceneType::lean, lean_scene_reference},
    {SceneType::walk, walk_scene_reference}};

} // namespace

SceneReference make_scene_reference(const SceneReferenceInputs& in) {
  for (const auto& [type, factory] : scene_references)
    if (type == in.scene.type)
      return factory(in);
  throw std::invalid_argument(std::string("Scene type = ") + to_string(in.scene.type) +
                              ": not a humanoid scene (stand, drop, lean or walk)");
}

} // namespace plantar::app
