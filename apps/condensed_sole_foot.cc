#include "apps/condensed_sole_foot.h"

#include "apps/scene.h"
#include "coupling/condensed_sole.h"
#include "coupling/reduced_sole.h"
#include "fem/field_output.h"
#include "fem/material_table.h"

#include <Eigen/Cholesky>

#include <array>
#include <iostream>

namespace plantar::app {

namespace {
constexpr const char* linear_sole_remedy =
    "the linear (small-strain) sole is far outside its validity: use Sole/Model = hyperelastic "
    "(large strains), a stiffer sole (E of Sole/Materials) or a gentler load (e.g. a smaller "
    "Simulation/Release height)";
} // namespace

CondensedSoleFoot::CondensedSoleFoot(const Scene& scene) : thickness_(scene.sole.thickness) {
  const SoleValidityParameters& validity = scene.sole_validity;
  compression_limit_ = {"sole_compression",          "linear sole compression / thickness",
                        "Sole/Compression warning",  "Sole/Max compression",
                        ValidityLimit::Bound::upper, validity.compression_warning,
                        validity.max_compression,    linear_sole_remedy};
  strain_limit_ = {"sole_strain",
                   "linear sole strain |u| / thickness",
                   "Sole/Strain warning",
                   "Sole/Max strain",
                   ValidityLimit::Bound::upper,
                   validity.strain_warning,
                   validity.max_strain,
                   linear_sole_remedy};
  dealii::Triangulation<3> tria;
  const auto groups = mesh_sole(scene.sole, tria);
  const auto specs = fem::parse_material_specs(scene.sole.materials, "Sole/Materials");
  const fem::MaterialTable materials(specs, groups);
  coupling::CondensationParameters condensation;
  condensation.attached_boundary = groups.surface("top");
  condensation.contact_boundary = groups.surface("bottom");
  condensation.degree = scene.sole.degree;
  // A reduced sole (a grid, or auto) keeps the factorization of K instead of C: its C_r costs
  // 3P solves, and its fields come from the patch forces (coupling/condensed_sole.h).
  const SoleReductionParameters& reduction = scene.sole_reduction;
  const bool reduce = reduction.reduced();
  if (reduce)
    condensation.form = coupling::CondensationParameters::Form::factorization;
  sole_ = std::make_unique<coupling::CondensedSole>(tria, materials, condensation);
  const auto& positions = sole_->contact_positions();
  int nx = reduction.patches_x, ny = reduction.patches_y;
  Eigen::VectorXd weights; // empty: equal shares
  if (reduce && reduction.area_weights)
    weights = coupling::pressure_weights(node_areas(0));
  if (reduction.automatic) {
    const coupling::ReductionChoice choice =
        coupling::choose_reduction(*sole_, reduction.tolerance, reduction.spacing, weights,
                                   reduction.basis, reduction.quantity);
    nx = ny = choice.grid;
    reduction_reached_ = choice.reached;
    if (!choice.reached) {
      std::cerr << "warning: Sole/Reduced patches = auto: no grid of fewer patches than the "
                << positions.rows()
                << " contact nodes meets Sole/Reduction tolerance = " << reduction.tolerance
                << " on Sole/Reduction quantity = " << reduction_quantity_name(reduction.quantity)
                << "; the full condensed sole is used\n";
      // The full sole needs C: condensed again in the dense form (`positions` referred to the
      // replaced sole).
      condensation.form = coupling::CondensationParameters::Form::dense;
      sole_ = std::make_unique<coupling::CondensedSole>(tria, materials, condensation);
      set_patch(sole_->contact_positions().transpose(), sole_->compliance(),
                scene.sole.damping_time);
      return;
    }
  }
  if (nx == 0) {
    set_patch(positions.transpose(), sole_->compliance(), scene.sole.damping_time);
    return;
  }
  // Reduced sole: one contact per patch (a grid cell, or a grid vertex's hat), with the
  // compliance C_r = A^T C A (coupling/reduced_sole.h).
  reduced_ = std::make_unique<coupling::ReducedSole>(
      *sole_, coupling::ReducedSole::grid_shares(positions, nx, ny, reduction.spacing,
                                                 reduction.basis, weights));
  reduced_factor_ = std::make_unique<Eigen::LDLT<Eigen::MatrixXd>>(reduced_->compliance());
  const Eigen::Vector3d origin = positions.colwise().mean().transpose();
  reduction_x_ = nx;
  reduction_y_ = ny;
  reduction_estimate_ =
      coupling::reduction_error_estimate(sole_->rigid_motion_stiffness(), *reduced_, origin);
  pressure_estimate_ =
      coupling::pressure_error_estimate(sole_->rigid_motion_forces(), *reduced_, origin);
  set_patch(reduced_->patch_positions().transpose(), reduced_->compliance(),
            scene.sole.damping_time);
  if (!scene.output.write_vtu)
    sole_->release_factorization(); // no fields to recover: keep C_r alone
}

bool CondensedSoleFoot::has_fields() const {
  return !reduced_ || sole_->has_solver();
}

void CondensedSoleFoot::write_fields(int foot, const multibody::SE3& placement,
                                     const std::filesystem::path& path) const {
  if (!reduced_) {
    SolePatchFoot::write_fields(foot, placement, path);
    return;
  }
  // The reduced sole's patch displacements U (sole frame) are those of the patch forces
  // F_e = C_r^-1 U (F_e = F without damping); shared by the patches' nodes, f = A F_e, they
  // give the field u = K^-1 B f, whose patch means A^T u_c are U. The nodes' forces written
  // are the model's, A F.
  const coupling::PadState& state = pad(foot);
  const Eigen::Matrix3d to_sole = placement.rotation.transpose();
  const int n_p = reduced_->n_patches(), n = reduced_->n_nodes();
  Eigen::VectorXd u_patch(3 * n_p);
  Eigen::Matrix3Xd f_patch(3, n_p); // world
  for (int j = 0; j < n_p; ++j) {
    u_patch.segment<3>(3 * j) =
        to_sole * state.node_to_world(j, state.displacement().segment<3>(3 * j));
    f_patch.col(j) = state.node_to_world(j, state.node_force(j));
  }
  const Eigen::VectorXd f_elastic = reduced_factor_->solve(u_patch);
  Eigen::VectorXd node_force = Eigen::VectorXd::Zero(3 * n);
  PadNodeState nodes{Eigen::Matrix3Xd(3, n), Eigen::Matrix3Xd::Zero(3, n)};
  const coupling::ReducedSole::ShareMatrix& shares = reduced_->shares();
  for (int j = 0; j < n_p; ++j)
    for (coupling::ReducedSole::ShareMatrix::InnerIterator it(shares, j); it; ++it) {
      node_force.segment<3>(3 * it.row()) += it.value() * f_elastic.segment<3>(3 * j);
      nodes.force.col(it.row()) += it.value() * f_patch.col(j);
    }
  sole_->displacement_of_forces(node_force, field_);
  const auto& dofs = sole_->contact_dofs();
  for (int k = 0; k < n; ++k)
    nodes.displacement.col(k) =
        placement.rotation *
        Eigen::Vector3d(field_(dofs[k][0]), field_(dofs[k][1]), field_(dofs[k][2]));
  const SoleMesh mesh = sole_mesh(foot);
  const PadFieldMesh field_mesh{mesh.dof_handler, mesh.discretization, mesh.contact_dofs,
                                &node_areas(foot)};
  write_pad_fields(
      field_mesh, nodes,
      [this](const Eigen::VectorXd&, dealii::Vector<double>&) -> const dealii::Vector<double>& {
        return field_;
      },
      *stress_postprocessor(foot), placement, path, cell_fields(foot));
}

void CondensedSoleFoot::summarize(HumanoidSummary& summary) const {
  SolePatchFoot::summarize(summary);
  summary.sole_reduction_x = reduction_x_;
  summary.sole_reduction_y = reduction_y_;
  summary.sole_reduction_estimate = reduction_estimate_;
  summary.sole_reduction_pressure_estimate = pressure_estimate_;
  summary.sole_reduction_reached = reduction_reached_;
}

CondensedSoleFoot::~CondensedSoleFoot() = default;

void CondensedSoleFoot::check_validity(const multibody::Data& data,
                                       ValidityMonitor& monitor) const {
  // One value per quantity and step: the larger foot's (NaN wins).
  std::array<double, 2> compression{}, displacement{};
  for (int foot = 0; foot < 2; ++foot)
    node_deformation(foot, data, compression[foot], displacement[foot]);
  const auto larger = [](const std::array<double, 2>& v) { return v[1] > v[0] || v[1] != v[1]; };
  const int c = larger(compression) ? 1 : 0, d = larger(displacement) ? 1 : 0;
  monitor.check(compression_limit_, compression[c] / thickness_, c ? "left sole" : "right sole");
  monitor.check(strain_limit_, displacement[d] / thickness_, d ? "left sole" : "right sole");
}

SolePatchFoot::SoleMesh CondensedSoleFoot::sole_mesh(int foot) const {
  (void)foot; // one sole for both feet
  return {&sole_->elasticity().dof_handler(), &sole_->elasticity().discretization(),
          &sole_->contact_dofs()};
}

const Eigen::VectorXd& CondensedSoleFoot::node_areas(int foot) const {
  (void)foot;
  if (area_.size() == 0) {
    const int n_c = sole_->n_contacts();
    Eigen::VectorXd unit_load(3 * n_c);
    sole_->contact_load(Eigen::Vector3d(0, 0, 1), unit_load);
    area_.resize(n_c);
    for (int k = 0; k < n_c; ++k)
      area_[k] = unit_load[3 * k + 2];
  }
  return area_;
}

const dealii::Vector<double>&
CondensedSoleFoot::displacement_field(int foot, const Eigen::VectorXd& contact_u,
                                      dealii::Vector<double>& workspace) const {
  (void)foot;
  sole_->recover(contact_u, workspace); // u_n = -K_nn^-1 K_nc u_c
  return workspace;
}

std::unique_ptr<dealii::DataPostprocessor<3>>
CondensedSoleFoot::stress_postprocessor(int foot) const {
  (void)foot;
  return std::make_unique<fem::StressPostprocessor>(sole_->elasticity().materials());
}

} // namespace plantar::app
