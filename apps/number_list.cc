#include "apps/number_list.h"

#include <deal.II/base/utilities.h>

#include <cmath>
#include <sstream>
#include <stdexcept>

namespace plantar::app {

std::optional<double> to_number(const std::string& text) {
  std::size_t used = 0;
  double value = 0;
  try {
    value = std::stod(text, &used);
  } catch (const std::exception&) {
    return std::nullopt;
  }
  if (text.find_first_not_of(" \t", used) != std::string::npos || !std::isfinite(value))
    return std::nullopt;
  return value;
}

std::string number_text(double value) {
  std::ostringstream out;
  out << value;
  return out.str();
}

std::vector<double> parse_numbers(const std::string& text, const std::string& parameter,
                                  std::size_t min_count, std::size_t max_count) {
  std::vector<double> values;
  for (const std::string& item : dealii::Utilities::split_string_list(text, ',')) {
    const std::optional<double> value = to_number(item);
    if (!value)
      throw std::invalid_argument(parameter + " = '" + text + "': '" + item +
                                  "' is not a finite number");
    values.push_back(*value);
  }
  if (values.size() < min_count || values.size() > max_count) {
    std::ostringstream msg;
    msg << parameter << " = '" << text << "': " << values.size() << " numbers, expected "
        << min_count << (min_count == max_count ? "" : " or " + std::to_string(max_count));
    throw std::invalid_argument(msg.str());
  }
  return values;
}

} // namespace plantar::app
