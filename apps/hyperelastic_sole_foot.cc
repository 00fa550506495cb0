#include "apps/hyperelastic_sole_foot.h"

#include "apps/scene.h"
#include "coupling/nonlinear_condensed_sole.h"
#include "fem/field_output.h"
#include "fem/hyperelastic_material_table.h"
#include "fem/visco_hyperelastic_fields.h"

#include <stdexcept>

namespace plantar::app {
namespace {

using dealii::DataComponentInterpretation::component_is_scalar;

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

} // namespace

HyperelasticSoleFoot::HyperelasticSoleFoot(const Scene& scene) : thickness_(scene.sole.thickness) {
  jacobian_limit_ = {"sole_min_jacobian",
                     "hyperelastic sole min det F",
                     "Sole/Jacobian warning",
                     "Sole/Min jacobian",
                     ValidityLimit::Bound::lower,
                     scene.sole_validity.jacobian_warning,
                     scene.sole_validity.min_jacobian,
                     "elements nearly inverted: use a smaller Simulation/Time step, a finer mesh "
                     "(Sole/Mesh size) or Sole/Formulation = mixed (nearly incompressible "
                     "rubber), or a stiffer sole"};
  if (scene.sole_reduction.reduced())
    throw std::invalid_argument("Sole/Model = hyperelastic cannot be combined with a reduced "
                                "sole (Sole reduction): use one or the other");
  dealii::Triangulation<3> tria;
  const auto groups = mesh_sole(scene.sole, tria);
  const fem::HyperelasticMaterialTable laws(
      fem::parse_material_specs(scene.sole.materials, "Sole/Materials"), groups);
  viscous_ = laws.has_viscosity();
  if (viscous_ && scene.sole.damping_time != 0.0)
    throw std::invalid_argument(
        "Sole/Damping time = " + std::to_string(scene.sole.damping_time) +
        " s: a visco-hyperelastic sole (beta<i>/G<i>, tau<i> in Sole/Materials) dissipates "
        "through its branches, allowed 0 (no Kelvin-Voigt damping on top)");
  coupling::NonlinearCouplingParameters parameters;
  parameters.sole.attached_boundary = groups.surface("top");
  parameters.sole.contact_boundary = groups.surface("bottom");
  parameters.sole.newton.formulation = scene.sole.mixed
                                           ? fem::NonlinearSettings::Formulation::mixed
                                           : fem::NonlinearSettings::Formulation::displacement;
  parameters.sole.recondensation_tolerance = scene.sole.recondensation_tolerance;
  parameters.check_tolerance = scene.sole.check_tolerance;
  if (viscous_) // one update() per step: the internal variables advance with the loop's time
    parameters.sole.time_step = scene.simulation.time_step;
  for (auto& sole : soles_)
    sole = std::make_unique<coupling::NonlinearCondensedSole>(tria, laws, scene.sole.degree,
                                                              parameters);
  set_patch(soles_[0]->contact_positions().transpose(), soles_[0]->compliance(),
            scene.sole.damping_time);
  const int n = n_nodes();
  forces_.setZero(3 * n);
  offset_.setZero(3 * n);
  compliance_.setZero(3 * n, 3 * n);
}

HyperelasticSoleFoot::~HyperelasticSoleFoot() = default;

void HyperelasticSoleFoot::update(const multibody::Data& data) {
  for (int foot = 0; foot < 2; ++foot) {
    coupling::NonlinearCondensedSole& sole = *soles_[foot];
    const multibody::Frame& frame = model_->frames[sole_frames_[foot]];
    // Node forces in the sole frame: world -> body -> sole.
    const Eigen::Matrix3d world_to_sole =
        frame.placement.rotation.transpose() * data.oMi[frame.body].rotation.transpose();
    for (int k = 0; k < n_nodes(); ++k) {
      const Eigen::Vector3d f = node_force_world(foot, k); // F at the step's end
      forces_.segment<3>(3 * k) = world_to_sole * f;
    }
    coupling::NonlinearUpdateReport report;
    try {
      report = sole.update(forces_);
    } catch (const std::exception& e) {
      throw std::runtime_error(std::string(foot == 0 ? "right" : "left") +
                               " hyperelastic sole: " + e.what() +
                               ": use a smaller Simulation/Time step (smaller force changes per "
                               "step), a finer mesh (Sole/Mesh size) or Sole/Formulation = mixed "
                               "(nearly incompressible rubber)");
    }
    if (!report.recondensed && !report.offset_moved)
      continue;
    // Body frame: R C R^T per 3x3 block and R d per node, R = sole -> body rotation.
    const Eigen::Matrix3d& r = frame.placement.rotation;
    const int n = sole.n_contacts();
    for (int i = 0; i < n; ++i)
      offset_.segment<3>(3 * i) = r * sole.offset().segment<3>(3 * i);
    if (!report.recondensed) { // viscous regions: the creep moved d only
      pad_state(foot).set_offset(offset_);
      pad_state(foot).set_lifted_offset(true); // lifted, the sole keeps recovering (U = d)
      continue;
    }
    for (int i = 0; i < n; ++i)
      for (int j = 0; j < n; ++j)
        compliance_.block<3, 3>(3 * i, 3 * j) =
            r * sole.compliance().block<3, 3>(3 * i, 3 * j) * r.transpose();
    set_patch_compliance(foot, compliance_, offset_);
  }
}

void HyperelasticSoleFoot::check_validity(const multibody::Data& data,
                                          ValidityMonitor& monitor) const {
  (void)data;
  const double j_right = soles_[0]->sole().elasticity().min_jacobian();
  const double j_left = soles_[1]->sole().elasticity().min_jacobian();
  const bool left = j_left < j_right || j_left != j_left;
  monitor.check(jacobian_limit_, left ? j_left : j_right, left ? "left sole" : "right sole");
}

void HyperelasticSoleFoot::summarize(HumanoidSummary& summary) const {
  SolePatchFoot::summarize(summary);
  summary.sole_newton_checks = soles_[0]->n_checks() + soles_[1]->n_checks();
  summary.sole_recondensations =
      static_cast<int>(soles_[0]->n_recondensations() + soles_[1]->n_recondensations());
  summary.sole_tolerated_error =
      std::max(soles_[0]->max_tolerated_error(), soles_[1]->max_tolerated_error());
  summary.sole_recondensation_tolerance = soles_[0]->parameters().sole.recondensation_tolerance;
  if (viscous_) { // the dashpots' dissipation, integrated at the Newton checks
    double dissipated = 0;
    for (const auto& sole : soles_)
      dissipated += fem::dissipated_energy(sole->sole().elasticity());
    summary.sole_dissipated_energy = dissipated;
  }
}

std::vector<PadCellField> HyperelasticSoleFoot::cell_fields(int foot) const {
  std::vector<PadCellField> out;
  if (!viscous_)
    return out;
  fem::ViscoelasticCellFields fields =
      fem::visco_hyperelastic_cell_fields(soles_[foot]->sole().elasticity());
  out.push_back({"dissipated_energy_density", std::move(fields.dissipated_energy_density)});
  for (std::size_t i = 0; i < fields.overstress.size(); ++i)
    out.push_back({"overstress_" + std::to_string(i + 1), std::move(fields.overstress[i])});
  return out;
}

SolePatchFoot::SoleMesh HyperelasticSoleFoot::sole_mesh(int foot) const {
  const fem::NonlinearSole& sole = soles_[foot]->sole();
  return {&sole.elasticity().dof_handler(), &sole.elasticity().discretization(),
          &sole.contact_dofs()};
}

const Eigen::VectorXd& HyperelasticSoleFoot::node_areas(int foot) const {
  (void)foot; // the same mesh under both feet
  if (area_.size() == 0) {
    const fem::NonlinearElasticity& problem = soles_[0]->sole().elasticity();
    area_ = consistent_areas(problem.dof_handler(), problem.discretization(),
                             soles_[0]->parameters().sole.contact_boundary,
                             soles_[0]->sole().contact_dofs());
  }
  return area_;
}

const dealii::Vector<double>&
HyperelasticSoleFoot::displacement_field(int foot, const Eigen::VectorXd& contact_u,
                                         dealii::Vector<double>& workspace) const {
  (void)contact_u, (void)workspace;
  return soles_[foot]->sole().elasticity().solution();
}

std::unique_ptr<dealii::DataPostprocessor<3>>
HyperelasticSoleFoot::stress_postprocessor(int foot) const {
  return std::make_unique<HyperelasticStress>(soles_[foot]->sole().elasticity().materials());
}

} // namespace plantar::app
