#include "fem/exception_text.h"

#include <deal.II/base/exceptions.h>

#include <sstream>

namespace plantar::fem {

std::string exception_text(const std::exception& error) {
  const auto* deal_ii = dynamic_cast<const dealii::ExceptionBase*>(&error);
  if (deal_ii == nullptr)
    return error.what();
  std::ostringstream info;
  deal_ii->print_info(info);
  std::string text = info.str();
  // Collapse the indentation and line breaks of deal.II's formatting.
  std::string plain;
  bool space = false;
  for (const char c : text) {
    if (c == '\n' || c == ' ' || c == '\t') {
      space = !plain.empty();
      continue;
    }
    if (space)
      plain += ' ';
    plain += c;
    space = false;
  }
  return plain;
}

} // namespace plantar::fem
