#pragma once
// Scene subsection "Sweep": the grid of `plantar sweep` (paper Fig. 3 and 4, and the time-step
// study). A sweep point is one run of the scene with one foot form (Robot/Foot forms, or
// Robot/Foot form), one time step and, for the FEM sole, one Young's modulus, Poisson ratio and
// (viscoelastic sole, law=prony) relaxation time of the first Prony branch; and up to
// SweepParameters::max_axes general axes, each any scene entry with its list of values
// ("Sweep/Axis 1 = Simulation/Theta = 0.5; 0.6; 1").

#include <deal.II/base/parameter_handler.h>

#include <string>
#include <vector>

namespace plantar::app {

/// One general axis of the grid: the scene entry Subsection/Entry (nested subsections allowed:
/// "A/B/Entry") set to each value in turn.
struct SweepAxis {
  std::string name;                     ///< "Sweep/Axis N"
  std::vector<std::string> subsections; ///< outermost first
  std::string entry;
  std::vector<std::string> values; ///< as written in the scene, each non-empty
  std::string path() const;        ///< "Subsection/.../Entry"
  /// The point directory's tag of value @p index: the entry's letters and digits, lower case,
  /// then the value with characters other than [A-Za-z0-9.+-] replaced by '-'.
  std::string tag(std::size_t index) const;
};

struct SweepParameters {
  static constexpr int max_axes = 4;
  std::vector<double> youngs_moduli;  ///< Pa, each > 0; empty: the scene's Sole/Materials
  std::vector<double> poisson_ratios; ///< each in (-1, 0.5); empty: the scene's Sole/Materials
  std::vector<double> time_steps;     ///< s, each in (0, 0.01]; empty: Simulation/Time step
  /// s, each > 0, replacing tau1= in Sole/Materials (law=prony); empty: the scene's.
  std::vector<double> relaxation_times;
  /// The general axes Sweep/Axis 1 ... Sweep/Axis max_axes that are set, in that order.
  std::vector<SweepAxis> axes;
  static void declare(dealii::ParameterHandler& prm);
  /// Throws std::invalid_argument naming "Sweep/<entry>", the value and the allowed range. An
  /// axis must name an entry declared in @p prm's scene outside subsection Sweep (checked by
  /// check_axes, which needs the whole scene's declarations).
  void parse(dealii::ParameterHandler& prm);
  /// Throws std::invalid_argument naming "Sweep/Axis N" if an axis names no declared scene
  /// entry of @p prm (at its root), names one in Sweep, or repeats another axis's entry.
  void check_axes(dealii::ParameterHandler& prm) const;
};

} // namespace plantar::app
