#include "apps/sweep_parameters.h"

#include <cctype>
#include <cmath>
#include <sstream>
#include <stdexcept>
#include <string>

namespace plantar::app {

namespace {

/// Parses "a, b, c" into numbers in (lo, hi] (or [lo, hi] ...): each checked by @p ok.
template <class Check>
std::vector<double> parse_list(const std::string& text, const std::string& name, Check ok,
                               const std::string& range) {
  std::vector<double> values;
  std::stringstream all(text);
  std::string item;
  while (std::getline(all, item, ',')) {
    if (item.find_first_not_of(" \t") == std::string::npos)
      continue;
    std::size_t used = 0;
    double value = 0;
    try {
      value = std::stod(item, &used);
    } catch (const std::exception&) {
      used = 0;
    }
    if (used == 0 || item.find_first_not_of(" \t", used) != std::string::npos || !ok(value))
      throw std::invalid_argument("Sweep/" + name + " = '" + text + "': value '" + item +
                                  "' must be a number " + range);
    values.push_back(value);
  }
  return values;
}

std::string trim(const std::string& text) {
  const auto first = text.find_first_not_of(" \t");
  if (first == std::string::npos)
    return "";
  return text.substr(first, text.find_last_not_of(" \t") - first + 1);
}

std::string axis_name(int number) {
  return "Axis " + std::to_string(number);
}

/// "Subsection/Entry = v1; v2" -> the axis; throws naming Sweep/<name>.
SweepAxis parse_axis(const std::string& text, const std::string& name) {
  const auto fail = [&](const std::string& why) {
    throw std::invalid_argument("Sweep/" + name + " = '" + text + "': " + why +
                                " (expected 'Subsection/Entry = value 1; value 2; ...')");
  };
  const auto equals = text.find('=');
  if (equals == std::string::npos)
    fail("no '='");
  SweepAxis axis;
  axis.name = "Sweep/" + name;
  std::stringstream path(trim(text.substr(0, equals)));
  std::string part;
  while (std::getline(path, part, '/'))
    axis.subsections.push_back(trim(part));
  if (axis.subsections.size() < 2)
    fail("the entry must be given with its subsection");
  for (const std::string& p : axis.subsections)
    if (p.empty())
      fail("an empty subsection or entry name");
  axis.entry = axis.subsections.back();
  axis.subsections.pop_back();
  std::stringstream values(text.substr(equals + 1));
  std::string value;
  while (std::getline(values, value, ';')) {
    value = trim(value);
    if (value.empty())
      fail("an empty value");
    axis.values.push_back(value);
  }
  if (axis.values.empty())
    fail("no value");
  for (std::size_t i = 0; i < axis.values.size(); ++i)
    for (std::size_t j = 0; j < i; ++j)
      if (axis.tag(i) == axis.tag(j))
        fail("values '" + axis.values[j] + "' and '" + axis.values[i] +
             "' give the same point directory tag '" + axis.tag(i) + "'");
  return axis;
}

} // namespace

std::string SweepAxis::path() const {
  std::string text;
  for (const std::string& s : subsections)
    text += s + "/";
  return text + entry;
}

std::string SweepAxis::tag(std::size_t index) const {
  std::string text;
  for (const char c : entry)
    if (std::isalnum(static_cast<unsigned char>(c)))
      text += static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  for (const char c : values.at(index))
    text +=
        std::isalnum(static_cast<unsigned char>(c)) || c == '.' || c == '+' || c == '-' ? c : '-';
  return text;
}

void SweepParameters::declare(dealii::ParameterHandler& prm) {
  prm.declare_entry("Young's moduli", "", dealii::Patterns::Anything(),
                    "plantar sweep: comma-separated Young's moduli E (Pa, > 0) replacing E= in "
                    "Sole/Materials (fem sole points). Empty: the scene's material.");
  prm.declare_entry("Poisson ratios", "", dealii::Patterns::Anything(),
                    "plantar sweep: comma-separated Poisson ratios nu (-1 < nu < 0.5) replacing "
                    "nu= in Sole/Materials (fem sole points). Empty: the scene's material.");
  prm.declare_entry("Relaxation times", "", dealii::Patterns::Anything(),
                    "plantar sweep: comma-separated relaxation times tau (s, > 0) replacing "
                    "tau1= (the first Prony branch's) in Sole/Materials of a viscoelastic sole "
                    "(law=prony, docs/viscoelastic.md; fem sole points). Empty: the scene's "
                    "material.");
  prm.declare_entry("Time steps", "", dealii::Patterns::Anything(),
                    "plantar sweep: comma-separated time steps (s, 0 < dt <= 0.01). Empty: "
                    "Simulation/Time step.");
  for (int n = 1; n <= max_axes; ++n)
    prm.declare_entry(axis_name(n), "", dealii::Patterns::Anything(),
                      "plantar sweep: a general axis 'Subsection/Entry = value 1; value 2; ...': "
                      "any scene entry outside Sweep, set to each value in turn (values "
                      "separated by ';'). The grid is the product of all axes. Empty: none.");
}

void SweepParameters::parse(dealii::ParameterHandler& prm) {
  youngs_moduli = parse_list(
      prm.get("Young's moduli"), "Young's moduli", [](double e) { return e > 0; }, "> 0 (Pa)");
  poisson_ratios = parse_list(
      prm.get("Poisson ratios"), "Poisson ratios", [](double nu) { return nu > -1 && nu < 0.5; },
      "in (-1, 0.5)");
  relaxation_times = parse_list(
      prm.get("Relaxation times"), "Relaxation times",
      [](double tau) { return tau > 0 && std::isfinite(tau); }, "> 0 (s)");
  time_steps = parse_list(
      prm.get("Time steps"), "Time steps", [](double dt) { return dt > 0 && dt <= 0.01; },
      "in (0, 0.01] (s)");
  axes.clear();
  for (int n = 1; n <= max_axes; ++n) {
    const std::string text = prm.get(axis_name(n));
    if (!trim(text).empty())
      axes.push_back(parse_axis(text, axis_name(n)));
  }
}

void SweepParameters::check_axes(dealii::ParameterHandler& prm) const {
  for (std::size_t a = 0; a < axes.size(); ++a) {
    const SweepAxis& axis = axes[a];
    const std::string name = axis.name + " = '" + axis.path() + " = ...'";
    if (axis.subsections.front() == "Sweep")
      throw std::invalid_argument(name + ": an axis cannot set a Sweep entry");
    const std::string path = axis.path();
    if (path == "Robot/Foot form" || path == "Robot/Foot forms" || path == "Simulation/Time step")
      throw std::invalid_argument(name + ": " + path +
                                  " has its own axis (Robot/Foot forms, Sweep/Time steps)");
    for (std::size_t b = 0; b < a; ++b)
      if (axes[b].path() == axis.path())
        throw std::invalid_argument(name + ": two axes set the same entry");
    std::size_t entered = 0;
    bool declared = true;
    try {
      for (const std::string& s : axis.subsections) {
        prm.enter_subsection(s);
        ++entered;
      }
      prm.get(axis.entry);
    } catch (...) {
      declared = false;
    }
    for (; entered > 0; --entered)
      prm.leave_subsection();
    if (!declared)
      throw std::invalid_argument(
          name + ": '" + axis.path() +
          "' is not an entry of the scene (plantar print-parameters lists them)");
  }
}

} // namespace plantar::app
