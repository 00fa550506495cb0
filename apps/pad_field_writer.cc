#include "apps/pad_field_writer.h"

#include "fem/atomic_file.h"

#include <deal.II/fe/fe_values.h>
#include <deal.II/numerics/data_out.h>

#include <stdexcept>
#include <string>

namespace plantar::app {
namespace {

using dealii::DataComponentInterpretation::component_is_part_of_vector;

/// A vector field rotated into the world frame: R u (R: sole -> world).
class RotatedVector : public dealii::DataPostprocessorVector<3> {
public:
  RotatedVector(const std::string& name, const Eigen::Matrix3d& rotation)
      : dealii::DataPostprocessorVector<3>(name, dealii::update_values), rotation_(rotation) {}
  void evaluate_vector_field(const dealii::DataPostprocessorInputs::Vector<3>& inputs,
                             std::vector<dealii::Vector<double>>& computed) const override {
    for (unsigned int p = 0; p < inputs.solution_values.size(); ++p) {
      const auto& u = inputs.solution_values[p];
      const Eigen::Vector3d w = rotation_ * Eigen::Vector3d(u(0), u(1), u(2));
      for (int d = 0; d < 3; ++d)
        computed[p](d) = w[d];
    }
  }

private:
  Eigen::Matrix3d rotation_;
};

/// Component @p component of a vector field, as a scalar.
class Component : public dealii::DataPostprocessorScalar<3> {
public:
  Component(const std::string& name, unsigned int component)
      : dealii::DataPostprocessorScalar<3>(name, dealii::update_values), component_(component) {}
  void evaluate_vector_field(const dealii::DataPostprocessorInputs::Vector<3>& inputs,
                             std::vector<dealii::Vector<double>>& computed) const override {
    for (unsigned int p = 0; p < inputs.solution_values.size(); ++p)
      computed[p](0) = inputs.solution_values[p](component_);
  }

private:
  unsigned int component_;
};

/// DataOut whose patches are moved rigidly (x -> R x + p) after build_patches().
class PlacedDataOut : public dealii::DataOut<3> {
public:
  void place(const Eigen::Matrix3d& rotation, const Eigen::Vector3d& translation) {
    auto move = [&](double x, double y, double z) {
      return Eigen::Vector3d(rotation * Eigen::Vector3d(x, y, z) + translation);
    };
    for (auto& patch : this->patches) {
      for (unsigned int v = 0; v < patch.reference_cell.n_vertices(); ++v) {
        auto& x = patch.vertices[v];
        const Eigen::Vector3d y = move(x[0], x[1], x[2]);
        x = dealii::Point<3>(y.x(), y.y(), y.z());
      }
      if (patch.points_are_available) { // mapped points: the last 3 rows of data
        const unsigned int r = patch.data.n_rows() - 3;
        for (unsigned int j = 0; j < patch.data.n_cols(); ++j) {
          const Eigen::Vector3d y =
              move(patch.data(r, j), patch.data(r + 1, j), patch.data(r + 2, j));
          for (int d = 0; d < 3; ++d)
            patch.data(r + d, j) = static_cast<float>(y[d]);
        }
      }
    }
  }
};

} // namespace

void write_pad_fields(const PadFieldMesh& mesh, const coupling::PadState& pad,
                      const FieldRecovery& recover, const dealii::DataPostprocessor<3>& stress,
                      const multibody::SE3& placement, const std::filesystem::path& path,
                      const std::vector<PadCellField>& cell_fields) {
  const int n_c = pad.n_nodes();
  const Eigen::VectorXd& u_contact = pad.displacement(); // (n, t1, t2) per node
  PadNodeState nodes{Eigen::Matrix3Xd(3, n_c), Eigen::Matrix3Xd(3, n_c)};
  for (int k = 0; k < n_c; ++k) {
    nodes.displacement.col(k) = pad.node_to_world(k, u_contact.segment<3>(3 * k));
    nodes.force.col(k) = pad.node_to_world(k, pad.node_force(k)); // at the step's end
  }
  write_pad_fields(mesh, nodes, recover, stress, placement, path, cell_fields);
}

void write_pad_fields(const PadFieldMesh& mesh, const PadNodeState& nodes,
                      const FieldRecovery& recover, const dealii::DataPostprocessor<3>& stress,
                      const multibody::SE3& placement, const std::filesystem::path& path,
                      const std::vector<PadCellField>& cell_fields) {
  const Eigen::VectorXd& area = *mesh.node_areas;
  const Eigen::Matrix3d& rotation = placement.rotation; // mesh -> world
  const auto& dofs = *mesh.contact_dofs;
  const int n_c = static_cast<int>(dofs.size());
  if (nodes.displacement.cols() != n_c || nodes.force.cols() != n_c)
    throw std::invalid_argument("write_pad_fields: " + std::to_string(nodes.displacement.cols()) +
                                " node displacements and " + std::to_string(nodes.force.cols()) +
                                " forces for " + std::to_string(n_c) + " contact nodes");
  const auto n = static_cast<unsigned int>(mesh.dof_handler->n_dofs());
  dealii::Vector<double> contact_displacement(n), force(n), workspace;
  dealii::Vector<double> pressure(n); // (contact_pressure, contact_node flag, 0) per node
  Eigen::VectorXd contact_u(3 * n_c); // mesh frame
  for (int k = 0; k < n_c; ++k) {
    const Eigen::Vector3d u = nodes.displacement.col(k);
    const Eigen::Vector3d f = nodes.force.col(k);
    contact_u.segment<3>(3 * k) = rotation.transpose() * u;
    for (int d = 0; d < 3; ++d) {
      contact_displacement[dofs[k][d]] = u[d];
      force[dofs[k][d]] = f[d];
    }
    pressure[dofs[k][0]] = area[k] > 0 ? f.z() / area[k] : 0.0;
    pressure[dofs[k][1]] = 1.0; // contact_node flag
  }
  const dealii::Vector<double>& field = recover(contact_u, workspace);
  const dealii::DoFHandler<3>& dof_handler = *mesh.dof_handler;
  const fem::Discretization& discretization = *mesh.discretization;
  const RotatedVector world_displacement("displacement", rotation);
  const Component contact_pressure("contact_pressure", 0), contact_node("contact_node", 1);
  const std::vector<dealii::DataComponentInterpretation::DataComponentInterpretation> vector(
      3, component_is_part_of_vector);
  PlacedDataOut out;
  out.attach_dof_handler(dof_handler);
  out.add_data_vector(field, world_displacement);
  out.add_data_vector(field, stress);
  out.add_data_vector(contact_displacement, std::vector<std::string>(3, "contact_displacement"),
                      dealii::DataOut<3>::type_dof_data, vector);
  out.add_data_vector(force, std::vector<std::string>(3, "contact_force"),
                      dealii::DataOut<3>::type_dof_data, vector);
  out.add_data_vector(pressure, contact_pressure);
  out.add_data_vector(pressure, contact_node);
  dealii::Vector<float> material_id(dof_handler.get_triangulation().n_active_cells());
  for (const auto& cell : dof_handler.active_cell_iterators())
    material_id(cell->active_cell_index()) = cell->material_id();
  out.add_data_vector(material_id, "material_id", dealii::DataOut<3>::type_cell_data);
  std::vector<dealii::Vector<float>> extra(cell_fields.size());
  for (std::size_t i = 0; i < cell_fields.size(); ++i) {
    extra[i].reinit(material_id.size());
    for (unsigned int c = 0; c < material_id.size(); ++c)
      extra[i](c) = static_cast<float>(cell_fields[i].values.at(c));
    out.add_data_vector(extra[i], cell_fields[i].name, dealii::DataOut<3>::type_cell_data);
  }
  const unsigned int subdivisions =
      discretization.kind == fem::CellKind::hexahedron ? discretization.degree : 1;
  out.build_patches(*discretization.mapping, subdivisions);
  out.place(rotation, placement.translation);
  dealii::DataOutBase::VtkFlags flags;
  flags.compression_level = dealii::DataOutBase::VtkFlags::best_speed; // not best_compression
  out.set_flags(flags);
  fem::write_file_atomically(path, [&](std::ostream& stream) { out.write_vtu(stream); });
}

Eigen::VectorXd
consistent_areas(const dealii::DoFHandler<3>& dof_handler,
                 const fem::Discretization& discretization, dealii::types::boundary_id bottom,
                 const std::vector<std::array<dealii::types::global_dof_index, 3>>& dofs) {
  const auto& fe = *discretization.fe;
  dealii::FEFaceValues<3> face_values(*discretization.mapping, fe, discretization.face_quadrature,
                                      dealii::update_values | dealii::update_JxW_values);
  dealii::Vector<double> load(dof_handler.n_dofs());
  std::vector<dealii::types::global_dof_index> local(fe.n_dofs_per_cell());
  for (const auto& cell : dof_handler.active_cell_iterators())
    for (const unsigned int face : cell->face_indices()) {
      if (!cell->face(face)->at_boundary() || cell->face(face)->boundary_id() != bottom)
        continue;
      face_values.reinit(cell, face);
      cell->get_dof_indices(local);
      for (unsigned int i = 0; i < fe.n_dofs_per_cell(); ++i)
        if (fe.system_to_component_index(i).first == 2)
          for (unsigned int q = 0; q < face_values.n_quadrature_points; ++q)
            load(local[i]) += face_values.shape_value(i, q) * face_values.JxW(q);
    }
  Eigen::VectorXd area(dofs.size());
  for (std::size_t k = 0; k < dofs.size(); ++k)
    area[static_cast<Eigen::Index>(k)] = load(dofs[k][2]);
  return area;
}

} // namespace plantar::app
