#pragma once
// A free-floating uniform block (one URDF link, CoM at the link origin) standing for a foot
// that carries the robot's mass, for the sole-in-the-loop tests.
#include "multibody/model.h"
#include "multibody/urdf_loader.h"

#include <cstdio>

namespace plantar::test {

/// @param mass kg. @param length, width, height m (x, y, z): box inertia m/12 (b^2 + c^2).
inline multibody::Model foot_block_model(double mass, double length, double width, double height) {
  const double ixx = mass / 12 * (width * width + height * height),
               iyy = mass / 12 * (length * length + height * height),
               izz = mass / 12 * (length * length + width * width);
  char xml[1024];
  std::snprintf(xml, sizeof xml,
                "<robot name=\"foot\"><link name=\"foot\"><inertial><origin xyz=\"0 0 0\"/>"
                "<mass value=\"%.17g\"/><inertia ixx=\"%.17g\" ixy=\"0\" ixz=\"0\" iyy=\"%.17g\" "
                "iyz=\"0\" izz=\"%.17g\"/></inertial></link></robot>",
                mass, ixx, iyy, izz);
  return multibody::build_model_from_urdf_string(xml, {}, "foot block");
}

} // namespace plantar::test
