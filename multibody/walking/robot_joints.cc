#include "multibody/walking/robot_joints.h"

namespace plantar::walking {

const std::array<std::string, n_robot_joints>& robot_joint_names() {
  static const std::array<std::string, n_robot_joints> names = [] {
    std::array<std::string, n_robot_joints> result;
    int i = 0;
    for (const char* group : {"RLEG", "LLEG"})
      for (int j = 0; j < 6; ++j)
        result[i++] = std::string(group) + "_JOINT" + std::to_string(j);
    for (const char* group : {"CHEST", "HEAD"})
      for (int j = 0; j < 2; ++j)
        result[i++] = std::string(group) + "_JOINT" + std::to_string(j);
    for (const char* group : {"RARM", "LARM"})
      for (int j = 0; j < 7; ++j)
        result[i++] = std::string(group) + "_JOINT" + std::to_string(j);
    return result;
  }();
  return names;
}

} // namespace plantar::walking
