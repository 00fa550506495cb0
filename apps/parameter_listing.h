#pragma once
// Human-readable listing of every declared parameter: name, default value,
// allowed values (the pattern) and documentation, grouped by subsection.

#include <deal.II/base/parameter_handler.h>

#include <ostream>

namespace plantar::app {

/// Writes the listing of @p prm's declared parameters to @p out.
void print_parameter_listing(const dealii::ParameterHandler& prm, std::ostream& out);

} // namespace plantar::app
