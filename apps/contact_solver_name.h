#pragma once
// The scene-file names of Contact/Solver's values (the table is in humanoid_parameters.cc).

#include "contact/solver_settings.h"

namespace plantar::app {

/// The scene-file name of @p solver: "gauss-seidel", "admm", "newton" or "auto".
const char* contact_solver_name(contact::ContactSolverType solver);

} // namespace plantar::app
