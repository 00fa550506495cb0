// Test helper: the HRP-2-like model (models/hrp2/hrp2.urdf) as a Humanoid, with the names of
// models/hrp2/robot.prm (robot names live in tests and scenes, not in library code).
#pragma once

#include "multibody/model.h"
#include "multibody/urdf_loader.h"
#include "multibody/walking/humanoid.h"

#include <cmath>
#include <string>

namespace plantar::walking::testing {

inline std::string hrp2_urdf() {
  return std::string(PLANTAR_SOURCE_DIR) + "/models/hrp2/hrp2.urdf";
}

/// HRP-2's description: base BODY, legs RLEG/LLEG_JOINT0..5 to RLEG/LLEG_LINK5, soles r_sole and
/// l_sole, joints in jrl-walkgen order, the half-sitting arms (15, -+10, 0, -30, 0, 0, 10) deg.
inline HumanoidDescription hrp2_description() {
  HumanoidDescription d;
  d.base_link = "BODY";
  d.foot_links = {"RLEG_LINK5", "LLEG_LINK5"};
  d.sole_frames = {"r_sole", "l_sole"};
  for (const char* group : {"RLEG", "LLEG"})
    for (int j = 0; j < 6; ++j)
      d.controlled_joints.push_back(std::string(group) + "_JOINT" + std::to_string(j));
  for (const char* group : {"CHEST", "HEAD"})
    for (int j = 0; j < 2; ++j)
      d.controlled_joints.push_back(std::string(group) + "_JOINT" + std::to_string(j));
  for (const char* group : {"RARM", "LARM"})
    for (int j = 0; j < 7; ++j)
      d.controlled_joints.push_back(std::string(group) + "_JOINT" + std::to_string(j));
  const double arm[7] = {15, -10, 0, -30, 0, 0, 10};
  for (int i = 0; i < 7; ++i) {
    if (arm[i] == 0)
      continue;
    d.posture.emplace_back("RARM_JOINT" + std::to_string(i), arm[i] * (M_PI / 180.0));
    d.posture.emplace_back("LARM_JOINT" + std::to_string(i),
                           (i == 1 ? -arm[i] : arm[i]) * (M_PI / 180.0));
  }
  return d;
}

/// The rigid HRP-2 model with a free base.
inline multibody::Model hrp2_model() {
  multibody::Model model = multibody::build_model_from_urdf(hrp2_urdf());
  add_sole_frames(model, hrp2_description());
  return model;
}

} // namespace plantar::walking::testing
