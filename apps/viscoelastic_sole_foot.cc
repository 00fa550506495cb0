#include "apps/viscoelastic_sole_foot.h"

#include "apps/scene.h"
#include "coupling/viscoelastic_pad.h"
#include "fem/field_output.h"
#include "fem/viscoelastic_material.h"
#include "multibody/stepper.h"

#include <stdexcept>

namespace plantar::app {

bool has_viscoelastic_material(const std::string& materials) {
  for (const auto& [name, spec] : fem::parse_material_specs(materials, "Sole/Materials"))
    if (spec.law == "prony")
      return true;
  return false;
}

ViscoelasticSoleFoot::ViscoelasticSoleFoot(const Scene& scene) : thickness_(scene.sole.thickness) {
  if (scene.sole_reduction.reduced())
    throw std::invalid_argument(
        "Sole/Reduced patches = " +
        (scene.sole_reduction.automatic ? std::string("auto")
                                        : std::to_string(scene.sole_reduction.patches_x) + ", " +
                                              std::to_string(scene.sole_reduction.patches_y)) +
        ": a viscoelastic sole (law=prony in Sole/Materials) needs the full sole, allowed 0");
  if (scene.sole.damping_time != 0.0)
    throw std::invalid_argument(
        "Sole/Damping time = " + std::to_string(scene.sole.damping_time) +
        " s: a viscoelastic sole (law=prony in Sole/Materials) dissipates through its Prony "
        "branches, allowed 0 (no Kelvin-Voigt damping on top)");
  dealii::Triangulation<3> tria;
  const auto groups = mesh_sole(scene.sole, tria);
  const fem::ViscoelasticMaterialTable materials(
      fem::parse_material_specs(scene.sole.materials, "Sole/Materials"), groups);
  fem::ViscoelasticCondensationParameters parameters;
  parameters.attached_boundary = groups.surface("top");
  parameters.contact_boundary = groups.surface("bottom");
  parameters.time_step = scene.simulation.time_step;
  // The per-cell dissipation is a .vtu field only: without the series a separable sole runs in
  // contact space (fem/viscoelastic_condensation.h).
  parameters.cell_dissipation = scene.output.write_vtu;
  bottom_ = parameters.contact_boundary;
  for (auto& sole : soles_) // sole frame = pad frame until attach places them on the feet
    sole = std::make_unique<coupling::ViscoelasticPad>(tria, scene.sole.degree, materials,
                                                       parameters, Eigen::Matrix3d::Identity(),
                                                       Eigen::Vector3d::Zero());
  set_patch(soles_[0]->contact_positions(), soles_[0]->compliance(), 0.0);
}

ViscoelasticSoleFoot::~ViscoelasticSoleFoot() = default;

void ViscoelasticSoleFoot::add_contacts(double friction) {
  SolePatchFoot::add_contacts(friction);
  for (int foot = 0; foot < 2; ++foot) {
    const multibody::Frame& frame = model_->frames[sole_frames_[foot]];
    soles_[foot]->set_placement(frame.placement.rotation, frame.placement.translation);
  }
}

void ViscoelasticSoleFoot::update(const multibody::Data& data) {
  (void)data; // the pad state holds the step's forces and contact frames
  for (int foot = 0; foot < 2; ++foot) {
    try {
      soles_[foot]->finish_step(pad_state(foot));
    } catch (const std::exception& e) {
      throw std::runtime_error(std::string(foot == 0 ? "right" : "left") +
                               " viscoelastic sole: " + e.what());
    }
  }
}

void ViscoelasticSoleFoot::summarize(HumanoidSummary& summary) const {
  SolePatchFoot::summarize(summary);
  summary.sole_dissipated_energy =
      soles_[0]->sole().dissipated_energy() + soles_[1]->sole().dissipated_energy();
}

SolePatchFoot::SoleMesh ViscoelasticSoleFoot::sole_mesh(int foot) const {
  const fem::ViscoelasticCondensation& sole = soles_[foot]->sole();
  return {&sole.dof_handler(), &soles_[foot]->discretization(), &sole.contact_dofs()};
}

const Eigen::VectorXd& ViscoelasticSoleFoot::node_areas(int foot) const {
  (void)foot; // the same mesh under both feet
  if (area_.size() == 0) {
    const fem::ViscoelasticCondensation& sole = soles_[0]->sole();
    area_ = consistent_areas(sole.dof_handler(), soles_[0]->discretization(), bottom_,
                             sole.contact_dofs());
  }
  return area_;
}

const dealii::Vector<double>&
ViscoelasticSoleFoot::displacement_field(int foot, const Eigen::VectorXd& contact_u,
                                         dealii::Vector<double>& workspace) const {
  (void)contact_u, (void)workspace;
  return soles_[foot]->sole().solution();
}

std::unique_ptr<dealii::DataPostprocessor<3>>
ViscoelasticSoleFoot::stress_postprocessor(int foot) const {
  (void)foot;
  return std::make_unique<fem::StrainPostprocessor>();
}

std::vector<PadCellField> ViscoelasticSoleFoot::cell_fields(int foot) const {
  fem::ViscoelasticCellFields fields = soles_[foot]->sole().cell_fields();
  std::vector<PadCellField> out;
  if (!fields.dissipated_energy_density.empty()) // empty in the contact-space form
    out.push_back({"dissipated_energy_density", std::move(fields.dissipated_energy_density)});
  out.push_back({"von_mises", std::move(fields.von_mises)});
  for (std::size_t i = 0; i < fields.overstress.size(); ++i)
    out.push_back({"overstress_" + std::to_string(i + 1), std::move(fields.overstress[i])});
  return out;
}

} // namespace plantar::app
