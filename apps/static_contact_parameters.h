#pragma once
// Subsection "Static contact" of a scene (Scene type = static contact, apps/static_contact_job.h):
// the foot's prescribed rigid displacement, friction, refinement and the solver's settings.

#include "fem/distributed_contact.h"

#include <deal.II/base/parameter_handler.h>

#include <array>

namespace plantar::app {

/// What the scene prescribes of the foot.
enum class FootControl {
  displacement, ///< the rigid displacement (Foot translation, Foot rotation)
  force, ///< Normal force and Moment x, y; t_z, theta_x, theta_y solved for (foot_load_control.h)
};

struct StaticContactParameters {
  FootControl control = FootControl::displacement;
  std::array<double, 3> translation{0, 0, -0.0001}; ///< m, the foot's translation
  std::array<double, 3> rotation{0, 0, 0};          ///< rad, rotation vector, each in [-0.2, 0.2]
  /// m, the rotation's point, from the centre of the sole's top face (mesh frame).
  std::array<double, 3> rotation_point{0, 0, 0};
  double initial_offset = 0; ///< m, [0, 0.1]: the ground lies this far below the sole's bottom
  double friction = 0.5;     ///< Coulomb's mu, [0, 10]
  int refinements = 0;       ///< global refinements of the gmsh mesh, [0, 8]
  double tolerance = 1e-10;  ///< relative complementarity residual, (0, 1e-2]
  int max_iterations = 50;   ///< Newton iterations, [1, 1000]
  fem::ContactLinearSolver linear_solver = fem::ContactLinearSolver::mumps;
  double normal_force = 600;    ///< N, (0, 1e5]: force control, the foot presses the sole down
  double moment_x = 0;          ///< N m, [-1e4, 1e4]: force control, about the rotation point
  double moment_y = 0;          ///< N m, [-1e4, 1e4]
  double load_tolerance = 1e-8; ///< force control: relative, (0, 1e-2]

  static void declare(dealii::ParameterHandler& prm);
  /// Throws std::invalid_argument naming the parameter, its value and the allowed range.
  void parse(dealii::ParameterHandler& prm);
};

} // namespace plantar::app
