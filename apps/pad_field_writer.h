#pragma once
// The .vtu of one deformable pad or FEM sole in the world (ParaView series, scene_vtk_writer.h):
// the recovered displacement field (world axes), the material's strain and stress, the contact
// nodes' displacement, force and pressure p_k = f_z,k / a_k (a_k = int_bottom N_k ds), a flag
// on the contact nodes and the material id per cell; the mesh placed rigidly by x -> R x + t.

#include "coupling/pad_state.h"
#include "fem/discretization.h"
#include "multibody/spatial.h"

#include <deal.II/dofs/dof_handler.h>
#include <deal.II/lac/vector.h>
#include <deal.II/numerics/data_postprocessor.h>

#include <Eigen/Core>

#include <array>
#include <filesystem>
#include <functional>
#include <string>
#include <vector>

namespace plantar::app {

/// A pad's (or sole's) mesh as the writer needs it.
struct PadFieldMesh {
  const dealii::DoFHandler<3>* dof_handler = nullptr;
  const fem::Discretization* discretization = nullptr;
  /// x, y, z dofs of each contact node, in the pad state's node order.
  const std::vector<std::array<dealii::types::global_dof_index, 3>>* contact_dofs = nullptr;
  /// Consistent areas a_k of the contact nodes (m^2, n).
  const Eigen::VectorXd* node_areas = nullptr;
};

/// Consistent areas a_k = int_bottom N_k ds (m^2) of the contact nodes @p dofs (their z dofs
/// used) of a sole on @p dof_handler; bottom = the faces with boundary id @p bottom.
Eigen::VectorXd
consistent_areas(const dealii::DoFHandler<3>& dof_handler,
                 const fem::Discretization& discretization, dealii::types::boundary_id bottom,
                 const std::vector<std::array<dealii::types::global_dof_index, 3>>& dofs);

/// A per-cell field of the .vtu: one value per active cell (indexed by active_cell_index()).
struct PadCellField {
  std::string name;
  std::vector<double> values;
};

/// The full displacement field (deal.II dof order, m, mesh frame) from the contact nodes'
/// displacements (3 n, mesh frame); may use the workspace given as second argument.
using FieldRecovery =
    std::function<const dealii::Vector<double>&(const Eigen::VectorXd&, dealii::Vector<double>&)>;

/// The contact nodes' state written to the .vtu, world components (3 x n each): displacement
/// (m) and force at the step's end (N).
struct PadNodeState {
  Eigen::Matrix3Xd displacement, force;
};

/// Writes @p pad's state on @p mesh as a .vtu at @p path (atomically): @p placement maps the
/// mesh frame to the world; @p stress adds the material's fields; @p cell_fields more per-cell
/// fields (e.g. a viscoelastic sole's dissipated energy density). Allocates (output steps only).
void write_pad_fields(const PadFieldMesh& mesh, const coupling::PadState& pad,
                      const FieldRecovery& recover, const dealii::DataPostprocessor<3>& stress,
                      const multibody::SE3& placement, const std::filesystem::path& path,
                      const std::vector<PadCellField>& cell_fields = {});
/// The same from the contact nodes' state @p nodes (one column per node of @p mesh), for a
/// model whose pad state is not per node (a reduced sole's patches).
void write_pad_fields(const PadFieldMesh& mesh, const PadNodeState& nodes,
                      const FieldRecovery& recover, const dealii::DataPostprocessor<3>& stress,
                      const multibody::SE3& placement, const std::filesystem::path& path,
                      const std::vector<PadCellField>& cell_fields = {});

} // namespace plantar::app
