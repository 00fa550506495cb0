#pragma once
// Subsections "Pad 1" ... "Pad 6" of a humanoid scene: deformable pads on named links
// (coupling/deformable_pad.h), e.g. knee, hand or heel pads, in contact with the ground beside
// the feet. A slot is used when its Link is set.

#include "coupling/deformable_pad.h"

#include <deal.II/base/parameter_handler.h>

#include <filesystem>
#include <vector>

namespace plantar::app {

/// One pad of a scene.
struct PadEntry {
  coupling::PadDescription description;
  double damping_time = 0; ///< Kelvin-Voigt beta (s, >= 0): D = beta K (coupling/pad_state.h)
  /// The run fails when a contact node is compressed by more than this fraction of the pad's
  /// thickness (a linear pad pushed past its validity), (0, 1].
  double max_compression = 0.5;
};

struct PadParameters {
  static constexpr int max_pads = 6; ///< subsections "Pad 1" ... "Pad 6"
  std::vector<PadEntry> pads;        ///< the slots whose Link is set, in slot order

  static void declare(dealii::ParameterHandler& prm);
  /// Throws std::invalid_argument naming the entry ("Pad 2/Placement"), its value and the range.
  void parse(dealii::ParameterHandler& prm, const std::filesystem::path& scene_directory);
};

} // namespace plantar::app
