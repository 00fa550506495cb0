#pragma once
// A one-paragraph message for any exception: deal.II's exceptions carry a
// long header (file, line, stack trace) in what(); users see only the
// "additional information" part.

#include <exception>
#include <string>

namespace plantar::fem {

/// The user-facing text of @p error (deal.II's print_info(), or what()).
std::string exception_text(const std::exception& error);

} // namespace plantar::fem
