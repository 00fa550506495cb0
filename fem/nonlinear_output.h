#pragma once
// Output of a nonlinear sole's deformed state for ParaView: displacement (m),
// per-cell minimum det F over the quadrature points, and material id, as a
// VTU file (written to a temporary file, then renamed).

#include "fem/nonlinear_elasticity.h"

#include <filesystem>

namespace plantar::fem {

/// Writes @p problem's current displacement field to @p path (.vtu). Q2 fields
/// are sampled on subdivided patches (hexahedra). Throws std::runtime_error
/// naming the file if it cannot be written.
void write_vtu(const NonlinearElasticity& problem, const std::filesystem::path& path);

/// Per-cell minimum of det F over the quadrature points (size n_active_cells).
dealii::Vector<float> cell_min_jacobian(const NonlinearElasticity& problem);

} // namespace plantar::fem
