#include "apps/sweep_parameters.h"

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

} // namespace

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
}

} // namespace plantar::app
