#pragma once
// A scene parameter with a fixed set of values (deal.II Selection): the table of (enum value,
// scene-file name) written once, giving the pattern, the parsing and the name of a value.

#include <deal.II/base/patterns.h>

#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

namespace plantar::app {

template <class Enum> using ChoiceTable = std::vector<std::pair<Enum, const char*>>;

/// The names of @p table joined by '|'.
template <class Enum> std::string choice_names(const ChoiceTable<Enum>& table) {
  std::string names;
  for (const auto& [value, name] : table)
    names += (names.empty() ? "" : "|") + std::string(name);
  return names;
}

/// The Selection pattern of @p table.
template <class Enum> dealii::Patterns::Selection choice_pattern(const ChoiceTable<Enum>& table) {
  return dealii::Patterns::Selection(choice_names(table));
}

/// The value named @p text. Throws std::invalid_argument naming @p parameter, @p text and the
/// allowed names (the Selection pattern normally stops a bad name before).
template <class Enum>
Enum parse_choice(const ChoiceTable<Enum>& table, const std::string& text,
                  const std::string& parameter) {
  for (const auto& [value, name] : table)
    if (text == name)
      return value;
  throw std::invalid_argument(parameter + " = '" + text + "': allowed " + choice_names(table));
}

/// The name of @p value in @p table ("?" if absent).
template <class Enum> const char* choice_name(const ChoiceTable<Enum>& table, Enum value) {
  for (const auto& [v, name] : table)
    if (v == value)
      return name;
  return "?";
}

} // namespace plantar::app
