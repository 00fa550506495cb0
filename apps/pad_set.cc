#include "apps/pad_set.h"

#include "apps/pad_field_writer.h"
#include "contact/terrain.h"
#include "coupling/contact_frame_compliance.h"
#include "fem/field_output.h"
#include "fem/material_table.h"
#include "fem/viscoelastic_material.h"
#include "multibody/stepper.h"

#include <limits>
#include <sstream>
#include <stdexcept>

namespace plantar::app {
namespace {

/// True if @p materials (fem::parse_material_specs syntax) has a region with law=prony.
bool is_viscoelastic(const std::string& materials, const std::string& parameter) {
  for (const auto& [name, spec] : fem::parse_material_specs(materials, parameter))
    if (spec.law == "prony")
      return true;
  return false;
}

} // namespace

PadSet::PadSet(const std::vector<PadEntry>& entries, double time_step, bool cell_dissipation)
    : entries_(entries) {
  for (const PadEntry& entry : entries_) {
    const coupling::PadDescription& description = entry.description;
    const std::string parameter = "pad '" + description.name + "' materials";
    Eigen::VectorXd area;
    try {
      if (is_viscoelastic(description.materials, parameter)) {
        description.validate();
        dealii::Triangulation<3> tria;
        double thickness = 0;
        const fem::PhysicalGroups groups = coupling::mesh_pad(description, tria, thickness);
        const fem::ViscoelasticMaterialTable materials(
            fem::parse_material_specs(description.materials, parameter), groups);
        fem::ViscoelasticCondensationParameters parameters;
        parameters.attached_boundary = groups.surface("top");
        parameters.contact_boundary = groups.surface("bottom");
        parameters.time_step = time_step;
        parameters.cell_dissipation = cell_dissipation;
        auto pad = std::make_unique<coupling::ViscoelasticPad>(tria, description.degree, materials,
                                                               parameters, description.rotation(),
                                                               description.translation);
        area = consistent_areas(pad->sole().dof_handler(), pad->discretization(),
                                parameters.contact_boundary, pad->sole().contact_dofs());
        link_nodes_.push_back(pad->contact_positions());
        thickness_.push_back(thickness);
        elastic_.emplace_back();
        viscoelastic_.push_back(std::move(pad));
      } else {
        auto pad = std::make_unique<coupling::DeformablePad>(description);
        const coupling::CondensedSole& condensed = pad->condensed();
        const int n = condensed.n_contacts();
        Eigen::VectorXd unit_load(3 * n);
        condensed.contact_load(Eigen::Vector3d(0, 0, 1), unit_load);
        area.resize(n);
        for (int k = 0; k < n; ++k)
          area[k] = unit_load[3 * k + 2];
        link_nodes_.push_back(pad->contact_positions());
        thickness_.push_back(pad->thickness());
        elastic_.push_back(std::move(pad));
        viscoelastic_.emplace_back();
      }
    } catch (const std::invalid_argument& e) {
      throw std::invalid_argument("pad " + description.name + ": " + e.what());
    } catch (const std::exception& e) {
      throw std::runtime_error("pad " + description.name + ": " + e.what());
    }
    areas_.push_back(std::move(area));
  }
}

PadSet::~PadSet() = default;

int PadSet::max_contacts() const {
  int n = 0;
  for (const Eigen::Matrix3Xd& nodes : link_nodes_)
    n += static_cast<int>(nodes.cols());
  return n;
}

void PadSet::resolve(const multibody::Model& model) {
  bodies_.clear();
  link_in_body_.clear();
  body_nodes_.clear();
  for (int i = 0; i < size(); ++i) {
    const coupling::PadDescription& pad = entries_[i].description;
    int frame = -1;
    try {
      frame = model.frame_id(pad.link);
    } catch (const std::invalid_argument&) {
      throw std::invalid_argument("Pad " + pad.name + "/Link = '" + pad.link +
                                  "': not a link of the robot");
    }
    const multibody::Frame& link = model.frames[frame];
    if (link.body == 0)
      throw std::invalid_argument("Pad " + pad.name + "/Link = '" + pad.link +
                                  "': fixed to the world, not to a moving link");
    bodies_.push_back(link.body);
    link_in_body_.push_back(link.placement);
    const Eigen::Matrix3Xd& nodes = link_nodes_[i];
    Eigen::Matrix3Xd body_nodes(3, nodes.cols());
    for (Eigen::Index k = 0; k < nodes.cols(); ++k)
      body_nodes.col(k) = link.placement.act_point(nodes.col(k));
    body_nodes_.push_back(std::move(body_nodes));
    if (viscoelastic_[i]) // placed in the body frame: its compliance and offset follow
      viscoelastic_[i]->set_placement(link.placement.rotation * pad.rotation(),
                                      link.placement.act_point(pad.translation));
  }
}

double PadSet::lowest_point(const multibody::Data& data, const contact::Terrain& terrain) const {
  double lowest = std::numeric_limits<double>::infinity();
  for (int i = 0; i < size(); ++i)
    for (Eigen::Index k = 0; k < body_nodes_[i].cols(); ++k) {
      const Eigen::Vector3d p = data.oMi[bodies_[i]].act_point(body_nodes_[i].col(k));
      lowest = std::min(lowest, p.z() - terrain.height(p.x(), p.y()));
    }
  return lowest;
}

void PadSet::attach(multibody::Stepper& stepper) {
  if (static_cast<int>(bodies_.size()) != size())
    throw std::logic_error("PadSet::attach before resolve");
  terrain_ = &stepper.terrain();
  states_.clear();
  for (int i = 0; i < size(); ++i) {
    const double friction = entries_[i].description.friction;
    if (viscoelastic_[i]) {
      states_.push_back(std::make_unique<coupling::PadState>(viscoelastic_[i]->compliance()));
      states_.back()->set_offset(viscoelastic_[i]->offset());
      stepper.add_deformable_patch(bodies_[i], body_nodes_[i], friction, *states_.back());
      continue;
    }
    const coupling::DeformablePad& pad = *elastic_[i];
    Eigen::MatrixXd compliance(pad.compliance().rows(), pad.compliance().cols());
    coupling::rotate_compliance(link_in_body_[i].rotation, pad.compliance(), compliance);
    states_.push_back(std::make_unique<coupling::PadState>(compliance));
    stepper.add_deformable_patch(bodies_[i], body_nodes_[i], friction, *states_.back());
    states_.back()->set_damping(entries_[i].damping_time);
  }
}

void PadSet::finish_step() {
  for (int i = 0; i < size(); ++i) {
    if (!viscoelastic_[i])
      continue;
    try {
      viscoelastic_[i]->finish_step(*states_[i]);
    } catch (const std::exception& e) {
      throw std::runtime_error("viscoelastic pad " + name(i) + ": " + e.what());
    }
  }
}

double PadSet::dissipated_energy() const {
  double energy = 0;
  for (const auto& pad : viscoelastic_)
    if (pad)
      energy += pad->sole().dissipated_energy();
  return energy;
}

multibody::SE3 PadSet::placement(int i, const multibody::Data& data) const {
  const coupling::PadDescription& pad = entries_[i].description;
  const multibody::SE3 pad_in_link(pad.rotation(), pad.translation);
  return data.oMi[bodies_[i]] * (link_in_body_[i] * pad_in_link);
}

void PadSet::report(int i, const multibody::Data& data, PadReport& out) const {
  const coupling::PadState& state = *states_[i];
  const Eigen::Matrix3d& body_rotation = data.oMi[bodies_[i]].rotation;
  // The pad's z axis in the world: u . R e_z > 0 pushes a bottom node into the pad.
  const Eigen::Vector3d inward =
      body_rotation * link_in_body_[i].rotation * entries_[i].description.rotation().col(2);
  out.force.setZero();
  out.depth = 0;
  out.compression = 0;
  const Eigen::VectorXd& u = state.displacement();
  for (int k = 0; k < state.n_nodes(); ++k) {
    out.force += state.node_to_world(k, state.node_force(k));
    const Eigen::Vector3d displacement = state.node_to_world(k, u.segment<3>(3 * k));
    const Eigen::Vector3d x = data.oMi[bodies_[i]].act_point(body_nodes_[i].col(k));
    out.depth = std::max(out.depth, -contact::terrain_gap(*terrain_, x + displacement));
    out.compression = std::max(out.compression, displacement.dot(inward));
  }
}

void PadSet::check(int i, const PadReport& report) const {
  const double limit = entries_[i].max_compression * thickness_[i];
  if (report.compression > limit) {
    std::ostringstream msg;
    msg << "pad " << name(i) << " compressed by " << report.compression
        << " m, more than Max compression " << entries_[i].max_compression << " x its thickness "
        << thickness_[i] << " m: past the linear pad's validity";
    throw std::runtime_error(msg.str());
  }
}

void PadSet::write_fields(int i, const multibody::Data& data,
                          const std::filesystem::path& path) const {
  if (viscoelastic_[i]) {
    const fem::ViscoelasticCondensation& sole = viscoelastic_[i]->sole();
    const PadFieldMesh mesh{&sole.dof_handler(), &viscoelastic_[i]->discretization(),
                            &sole.contact_dofs(), &areas_[i]};
    fem::ViscoelasticCellFields fields = sole.cell_fields();
    std::vector<PadCellField> cells;
    if (!fields.dissipated_energy_density.empty()) // kept only with the .vtu series
      cells.push_back({"dissipated_energy_density", std::move(fields.dissipated_energy_density)});
    cells.push_back({"von_mises", std::move(fields.von_mises)});
    for (std::size_t b = 0; b < fields.overstress.size(); ++b)
      cells.push_back({"overstress_" + std::to_string(b + 1), std::move(fields.overstress[b])});
    write_pad_fields(
        mesh, *states_[i],
        [&](const Eigen::VectorXd&, dealii::Vector<double>&) -> const dealii::Vector<double>& {
          return sole.solution();
        },
        fem::StrainPostprocessor(), placement(i, data), path, cells);
    return;
  }
  const coupling::CondensedSole& condensed = elastic_[i]->condensed();
  const PadFieldMesh mesh{&condensed.elasticity().dof_handler(),
                          &condensed.elasticity().discretization(), &condensed.contact_dofs(),
                          &areas_[i]};
  const fem::StressPostprocessor stress(condensed.elasticity().materials());
  write_pad_fields(
      mesh, *states_[i],
      [&](const Eigen::VectorXd& contact_u,
          dealii::Vector<double>& workspace) -> const dealii::Vector<double>& {
        condensed.recover(contact_u, workspace);
        return workspace;
      },
      stress, placement(i, data), path);
}

} // namespace plantar::app
