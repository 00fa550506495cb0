#include "apps/sole_patch_foot.h"

#include "contact/ground_frame.h"
#include "coupling/contact_frame_compliance.h"
#include "coupling/pad_state.h"
#include "fem/atomic_file.h"
#include "fem/mesh_generator.h"
#include "multibody/stepper.h"

#include <deal.II/numerics/data_out.h>

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

fem::PhysicalGroups SolePatchFoot::mesh_sole(const fem::SoleParameters& sole,
                                             dealii::Triangulation<3>& tria) {
  auto request = sole.mesh_request();
  if (request.cache_directory.empty())
    request.cache_directory = fem::default_mesh_cache();
  const auto msh = fem::generate_mesh(request);
  return fem::import_mesh(msh, {"top", "bottom"}, tria);
}

void SolePatchFoot::set_patch(Eigen::Matrix3Xd nodes, Eigen::MatrixXd compliance,
                              double damping_time) {
  nodes_ = std::move(nodes);
  compliance_ = std::move(compliance);
  damping_time_ = damping_time;
}

void SolePatchFoot::add_contacts(double friction) {
  for (int foot = 0; foot < 2; ++foot) {
    const multibody::Frame& frame = model_->frames[sole_frames_[foot]];
    const int n = n_nodes();
    Eigen::Matrix3Xd body_nodes(3, n);
    for (int k = 0; k < n; ++k)
      body_nodes.col(k) = frame.placement.act_point(nodes_.col(k));
    // C in the body frame: R C R^T per 3x3 block, R = sole -> body rotation
    // (identity "contact" frames: the stepper projects onto its own frames).
    const Eigen::MatrixXd identity_frames = Eigen::Matrix3d::Identity().replicate(1, n);
    Eigen::MatrixXd compliance(3 * n, 3 * n);
    coupling::rotate_compliance_to_contact_frames(compliance_, frame.placement.rotation,
                                                  identity_frames, compliance);
    pads_[foot] = std::make_unique<coupling::PadState>(compliance);
    stepper_->add_deformable_patch(frame.body, body_nodes, friction, *pads_[foot]);
    pads_[foot]->set_damping(damping_time_);
    for (int k = 0; k < n; ++k)
      feet_[foot].push_back({frame.body, body_nodes.col(k)});
  }
}

Eigen::Vector3d SolePatchFoot::node_force(int foot, int node) const {
  return pads_[foot]->node_force(node);
}

void SolePatchFoot::set_patch_compliance(int foot, const Eigen::MatrixXd& compliance,
                                         const Eigen::VectorXd& offset) {
  pads_[foot]->set_compliance(compliance, offset);
}

void SolePatchFoot::report(int foot, const multibody::Data& data, double dt,
                           FootReport& out) const {
  (void)dt; // node forces are forces at the step's end
  out.force.setZero();
  out.moment.setZero();
  out.depth = 0;
  const coupling::PadState& pad = *pads_[foot];
  for (int k = 0; k < n_nodes(); ++k) {
    const Node& c = feet_[foot][k];
    const Eigen::Vector3d f = contact::ground_to_world(pad.node_force(k));
    const Eigen::Vector3d x = data.oMi[c.body].act_point(c.position);
    out.force += f;
    out.moment.x() += f.z() * x.x();
    out.moment.y() += f.z() * x.y();
    double z = x.z();
    z += pad.displacement()[3 * k];
    out.depth = std::max(out.depth, -z);
  }
}

void SolePatchFoot::write_fields(int foot, const multibody::SE3& placement,
                                 const std::filesystem::path& path) const {
  const SoleMesh mesh = sole_mesh(foot);
  const Eigen::VectorXd& area = node_areas(foot);
  const coupling::PadState& pad = *pads_[foot];
  const Eigen::Matrix3d& rotation = placement.rotation;  // sole -> world
  const Eigen::VectorXd& u_contact = pad.displacement(); // (n, t1, t2) per node
  const auto& dofs = *mesh.contact_dofs;
  const int n_c = static_cast<int>(dofs.size());
  const auto n = static_cast<unsigned int>(mesh.dof_handler->n_dofs());
  dealii::Vector<double> contact_displacement(n), force(n), workspace;
  dealii::Vector<double> pressure(n); // (contact_pressure, contact_node flag, 0) per node
  Eigen::VectorXd contact_u(3 * n_c); // sole frame
  for (int k = 0; k < n_c; ++k) {
    const Eigen::Vector3d u = contact::ground_to_world(u_contact.segment<3>(3 * k));
    const Eigen::Vector3d f = contact::ground_to_world(pad.node_force(k)); // at the step's end
    contact_u.segment<3>(3 * k) = rotation.transpose() * u;
    for (int d = 0; d < 3; ++d) {
      contact_displacement[dofs[k][d]] = u[d];
      force[dofs[k][d]] = f[d];
    }
    pressure[dofs[k][0]] = area[k] > 0 ? f.z() / area[k] : 0.0;
    pressure[dofs[k][1]] = 1.0; // contact_node flag
  }
  const dealii::Vector<double>& field = displacement_field(foot, contact_u, workspace);
  const dealii::DoFHandler<3>& dof_handler = *mesh.dof_handler;
  const fem::Discretization& discretization = *mesh.discretization;
  const std::unique_ptr<dealii::DataPostprocessor<3>> stress = stress_postprocessor(foot);
  const RotatedVector world_displacement("displacement", rotation);
  const Component contact_pressure("contact_pressure", 0), contact_node("contact_node", 1);
  const std::vector<dealii::DataComponentInterpretation::DataComponentInterpretation> vector(
      3, component_is_part_of_vector);
  PlacedDataOut out;
  out.attach_dof_handler(dof_handler);
  out.add_data_vector(field, world_displacement);
  out.add_data_vector(field, *stress);
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
  const unsigned int subdivisions =
      discretization.kind == fem::CellKind::hexahedron ? discretization.degree : 1;
  out.build_patches(*discretization.mapping, subdivisions);
  out.place(rotation, placement.translation);
  dealii::DataOutBase::VtkFlags flags;
  flags.compression_level = dealii::DataOutBase::VtkFlags::best_speed; // not best_compression
  out.set_flags(flags);
  fem::write_file_atomically(path, [&](std::ostream& stream) { out.write_vtu(stream); });
}

} // namespace plantar::app
