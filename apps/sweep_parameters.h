#pragma once
// Scene subsection "Sweep": the grid of `plantar sweep` (paper Fig. 3 and 4, and the time-step
// study). A sweep point is one run of the scene with one foot form (Robot/Foot forms, or
// Robot/Foot form), one time step and, for the FEM sole, one Young's modulus, Poisson ratio and
// (viscoelastic sole, law=prony) relaxation time of the first Prony branch.

#include <deal.II/base/parameter_handler.h>

#include <vector>

namespace plantar::app {

struct SweepParameters {
  std::vector<double> youngs_moduli;  ///< Pa, each > 0; empty: the scene's Sole/Materials
  std::vector<double> poisson_ratios; ///< each in (-1, 0.5); empty: the scene's Sole/Materials
  std::vector<double> time_steps;     ///< s, each in (0, 0.01]; empty: Simulation/Time step
  /// s, each > 0, replacing tau1= in Sole/Materials (law=prony); empty: the scene's.
  std::vector<double> relaxation_times;
  static void declare(dealii::ParameterHandler& prm);
  /// Throws std::invalid_argument naming "Sweep/<entry>", the value and the allowed range.
  void parse(dealii::ParameterHandler& prm);
};

} // namespace plantar::app
