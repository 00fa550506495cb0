#pragma once
// Lists of numbers in scene entries ('0.1, 0.2, 0.3').

#include <cstddef>
#include <optional>
#include <string>
#include <vector>

namespace plantar::app {

/// The finite number that @p text is (surrounding blanks allowed), or nothing.
std::optional<double> to_number(const std::string& text);

/// @p value as a scene file writes it (the shortest of the default stream format, e.g. "0.1").
std::string number_text(double value);

/// Comma-separated finite numbers, between @p min_count and @p max_count of them. Throws
/// std::invalid_argument naming @p parameter, the text and what is wrong.
std::vector<double> parse_numbers(const std::string& text, const std::string& parameter,
                                  std::size_t min_count, std::size_t max_count);

} // namespace plantar::app
