#include "apps/scene_vtk_writer.h"

#include "contact/ground_frame.h"
#include "coupling/condensed_sole.h"
#include "coupling/nonlinear_condensed_sole.h"
#include "coupling/pad_state.h"
#include "fem/atomic_file.h"
#include "fem/field_output.h"
#include "multibody/kinematics.h"

#include <deal.II/fe/fe_values.h>
#include <deal.II/numerics/data_out.h>
#include <deal.II/numerics/data_postprocessor.h>

#include <cstdio>
#include <iomanip>

namespace plantar::app {
namespace {

using dealii::DataComponentInterpretation::component_is_part_of_vector;
using dealii::DataComponentInterpretation::component_is_scalar;

const char* const foot_names[2] = {"right", "left"};

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

/// Hyperelastic sole: Green-Lagrange strain E = (F^T F - I) / 2, Cauchy stress
/// sigma = P F^T / J (P of the cell's law with its volumetric part U'(J) of the displacement
/// field, also for the mixed formulation) and its von Mises stress, F = I + grad u.
class HyperelasticStress : public dealii::DataPostprocessor<3> {
public:
  explicit HyperelasticStress(const fem::HyperelasticMaterialTable& laws) : laws_(laws) {}
  void evaluate_vector_field(const dealii::DataPostprocessorInputs::Vector<3>& inputs,
                             std::vector<dealii::Vector<double>>& computed) const override {
    const auto cell = inputs.template get_cell<3>();
    const fem::HyperelasticLaw& law = laws_[cell->material_id()];
    fem::StressTangent st;
    for (unsigned int p = 0; p < inputs.solution_gradients.size(); ++p) {
      dealii::Tensor<2, 3> F = dealii::unit_symmetric_tensor<3>();
      for (unsigned int d = 0; d < 3; ++d)
        F[d] += inputs.solution_gradients[p][d];
      law.evaluate(F, true, st);
      const dealii::SymmetricTensor<2, 3> strain =
          0.5 * (dealii::symmetrize(dealii::transpose(F) * F) - dealii::unit_symmetric_tensor<3>());
      const dealii::SymmetricTensor<2, 3> cauchy =
          dealii::symmetrize(st.first_piola * dealii::transpose(F)) / dealii::determinant(F);
      for (unsigned int i = 0; i < 3; ++i)
        for (unsigned int j = 0; j < 3; ++j) {
          computed[p](3 * i + j) = strain[i][j];
          computed[p](9 + 3 * i + j) = cauchy[i][j];
        }
      computed[p](18) = fem::von_mises(cauchy);
    }
  }
  std::vector<std::string> get_names() const override {
    std::vector<std::string> names(9, "strain");
    names.resize(18, "stress");
    names.push_back("von_mises");
    return names;
  }
  std::vector<dealii::DataComponentInterpretation::DataComponentInterpretation>
  get_data_component_interpretation() const override {
    std::vector<dealii::DataComponentInterpretation::DataComponentInterpretation> kinds(
        18, dealii::DataComponentInterpretation::component_is_part_of_tensor);
    kinds.push_back(component_is_scalar);
    return kinds;
  }
  dealii::UpdateFlags get_needed_update_flags() const override { return dealii::update_gradients; }

private:
  const fem::HyperelasticMaterialTable& laws_;
};

/// Consistent areas a_k = int_bottom N_k ds (m^2) of the contact nodes @p dofs (z dofs) of a
/// sole on @p dof_handler, bottom = faces with boundary id @p bottom.
Eigen::VectorXd
node_areas(const dealii::DoFHandler<3>& dof_handler, const fem::Discretization& discretization,
           dealii::types::boundary_id bottom,
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

/// vtk/<stem>_NNNNNN.vtp for the links, .vtu for the soles.
std::string frame_name(const std::string& stem, int frame) {
  char number[16];
  std::snprintf(number, sizeof number, "_%06d", frame);
  return "vtk/" + stem + number + (stem == "links" ? ".vtp" : ".vtu");
}

} // namespace

SceneVtkWriter::SceneVtkWriter(const HumanoidSimulation& simulation,
                               const std::filesystem::path& urdf_file, double stick_radius,
                               const std::filesystem::path& directory)
    : directory_(directory), data_(simulation.model()) {
  shapes_ = make_link_shapes(simulation.model(), urdf_file, stick_radius);
  if (const coupling::CondensedSole* sole = simulation.sole()) {
    const auto n = static_cast<unsigned int>(sole->n_dofs());
    displacement_.reinit(n);
    contact_displacement_.reinit(n);
    force_.reinit(n);
    pressure_.reinit(n);
    const int n_c = sole->n_contacts();
    contact_u_.resize(3 * n_c);
    Eigen::VectorXd unit_load(3 * n_c);
    sole->contact_load(Eigen::Vector3d(0, 0, 1), unit_load);
    area_.resize(n_c);
    for (int k = 0; k < n_c; ++k)
      area_[k] = unit_load[3 * k + 2];
  } else if (const coupling::NonlinearCondensedSole* hyper = simulation.hyperelastic_sole(0)) {
    const fem::NonlinearElasticity& problem = hyper->sole().elasticity();
    const auto n = static_cast<unsigned int>(problem.dof_handler().n_dofs());
    contact_displacement_.reinit(n);
    force_.reinit(n);
    pressure_.reinit(n);
    contact_u_.resize(3 * hyper->n_contacts());
    area_ = node_areas(problem.dof_handler(), problem.discretization(),
                       hyper->parameters().sole.contact_boundary, hyper->sole().contact_dofs());
  }
  std::filesystem::create_directories(directory_ / "vtk");
}

SceneVtkWriter::~SceneVtkWriter() = default;

void SceneVtkWriter::write(const HumanoidSimulation& simulation) {
  const int frame = n_frames();
  multibody::forward_kinematics(simulation.model(), data_, simulation.q());
  write_links_vtp(simulation.model(), data_, shapes_, directory_ / frame_name("links", frame));
  if (simulation.sole() || simulation.hyperelastic_sole(0))
    for (int foot = 0; foot < 2; ++foot)
      write_sole(simulation, foot,
                 directory_ / frame_name(std::string("sole_") + foot_names[foot], frame));
  times_.push_back(simulation.time());
  write_pvd();
}

void SceneVtkWriter::write_sole(const HumanoidSimulation& simulation, int foot,
                                const std::filesystem::path& path) {
  const coupling::CondensedSole* linear = simulation.sole();
  const coupling::NonlinearCondensedSole* hyper = simulation.hyperelastic_sole(foot);
  const coupling::PadState& pad = *simulation.pad(foot);
  const multibody::SE3 placement =
      multibody::frame_placement(simulation.model(), data_, simulation.sole_frame(foot));
  const Eigen::Matrix3d& rotation = placement.rotation;  // sole -> world
  const Eigen::VectorXd& u_contact = pad.displacement(); // (n, t1, t2) per node
  const auto& dofs = linear ? linear->contact_dofs() : hyper->sole().contact_dofs();
  const int n_c = static_cast<int>(dofs.size());
  contact_displacement_ = 0;
  force_ = 0;
  pressure_ = 0;
  for (int k = 0; k < n_c; ++k) {
    const Eigen::Vector3d u = contact::ground_to_world(u_contact.segment<3>(3 * k));
    const Eigen::Vector3d f = contact::ground_to_world(pad.node_force(k)); // at the step's end
    contact_u_.segment<3>(3 * k) = rotation.transpose() * u;
    for (int d = 0; d < 3; ++d) {
      contact_displacement_[dofs[k][d]] = u[d];
      force_[dofs[k][d]] = f[d];
    }
    pressure_[dofs[k][0]] = area_[k] > 0 ? f.z() / area_[k] : 0.0;
    pressure_[dofs[k][1]] = 1.0; // contact_node flag
  }
  // Linear: recovered from u_c. Hyperelastic: the sole's state of its last Newton check.
  if (linear)
    linear->recover(contact_u_, displacement_);
  const dealii::Vector<double>& field =
      linear ? displacement_ : hyper->sole().elasticity().solution();
  const dealii::DoFHandler<3>& dof_handler =
      linear ? linear->elasticity().dof_handler() : hyper->sole().elasticity().dof_handler();
  const fem::Discretization& discretization =
      linear ? linear->elasticity().discretization() : hyper->sole().elasticity().discretization();
  std::unique_ptr<dealii::DataPostprocessor<3>> stress;
  if (linear)
    stress = std::make_unique<fem::StressPostprocessor>(linear->elasticity().materials());
  else
    stress = std::make_unique<HyperelasticStress>(hyper->sole().elasticity().materials());
  const RotatedVector world_displacement("displacement", rotation);
  const Component contact_pressure("contact_pressure", 0), contact_node("contact_node", 1);
  const std::vector<dealii::DataComponentInterpretation::DataComponentInterpretation> vector(
      3, component_is_part_of_vector);
  PlacedDataOut out;
  out.attach_dof_handler(dof_handler);
  out.add_data_vector(field, world_displacement);
  out.add_data_vector(field, *stress);
  out.add_data_vector(contact_displacement_, std::vector<std::string>(3, "contact_displacement"),
                      dealii::DataOut<3>::type_dof_data, vector);
  out.add_data_vector(force_, std::vector<std::string>(3, "contact_force"),
                      dealii::DataOut<3>::type_dof_data, vector);
  out.add_data_vector(pressure_, contact_pressure);
  out.add_data_vector(pressure_, contact_node);
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

void SceneVtkWriter::write_pvd() const {
  auto write = [&](const std::string& name, const std::vector<std::string>& stems) {
    fem::write_file_atomically(directory_ / name, [&](std::ostream& out) {
      out << std::setprecision(10)
          << "<?xml version=\"1.0\"?>\n<VTKFile type=\"Collection\" version=\"0.1\">\n"
          << "<Collection>\n";
      for (std::size_t i = 0; i < times_.size(); ++i)
        for (std::size_t part = 0; part < stems.size(); ++part)
          out << "<DataSet timestep=\"" << times_[i] << "\" part=\"" << part << "\" file=\""
              << frame_name(stems[part], static_cast<int>(i)) << "\"/>\n";
      out << "</Collection>\n</VTKFile>\n";
    });
  };
  std::vector<std::string> all{"links"};
  write("links.pvd", {"links"});
  if (!area_.size()) {
    write("scene.pvd", all);
    return;
  }
  for (const char* foot : foot_names) {
    all.push_back(std::string("sole_") + foot);
    write(std::string("sole_") + foot + ".pvd", {all.back()});
  }
  write("scene.pvd", all);
}

} // namespace plantar::app
