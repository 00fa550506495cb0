#include "contact/flat_terrain.h"

#include <cmath>
#include <stdexcept>
#include <string>

namespace plantar::contact {

FlatTerrain::FlatTerrain(double level) : level_(level) {
  if (!std::isfinite(level))
    throw std::invalid_argument("FlatTerrain: level = " + std::to_string(level) +
                                " m, allowed finite");
}

const Terrain& flat_ground() {
  static const FlatTerrain ground(0.0);
  return ground;
}

} // namespace plantar::contact
