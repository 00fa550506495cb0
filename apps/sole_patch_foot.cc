#include "apps/sole_patch_foot.h"

#include "apps/pad_field_writer.h"
#include "contact/terrain.h"
#include "coupling/contact_frame_compliance.h"
#include "coupling/pad_state.h"
#include "coupling/reduced_sole.h"
#include "fem/mesh_generator.h"
#include "multibody/stepper.h"

#include <Eigen/Cholesky>
#include <Eigen/LU>
#include <deal.II/fe/fe_values.h>

#include <algorithm>
#include <limits>

namespace plantar::app {
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
  // Pressed down uniformly by delta: f_z = C_zz^-1 delta 1, total k delta with k = 1^T C_zz^-1 1.
  const int n = n_nodes();
  Eigen::MatrixXd c_zz(n, n);
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j)
      c_zz(i, j) = compliance_(3 * i + 2, 3 * j + 2);
  stiffness_ = c_zz.ldlt().solve(Eigen::VectorXd::Ones(n)).sum();
}

Eigen::Vector2d SolePatchFoot::tilt_stiffness() const {
  const Eigen::Matrix<double, 6, 6> rigid =
      coupling::rigid_motion_stiffness(nodes_.transpose(), compliance_, nodes_.rowwise().mean());
  const Eigen::Matrix<double, 6, 6> flexibility = rigid.inverse();
  return {1 / flexibility(3, 3), 1 / flexibility(4, 4)};
}

void SolePatchFoot::summarize(HumanoidSummary& summary) const {
  summary.n_sole_nodes = n_nodes();
  summary.foot_stiffness = stiffness_;
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
    bodies_[foot] = frame.body;
    normal_in_body_[foot] = frame.placement.rotation.col(2);
  }
}

void SolePatchFoot::node_deformation(int foot, const multibody::Data& data, double& compression,
                                     double& displacement) const {
  const Eigen::Vector3d normal = data.oMi[bodies_[foot]].rotation * normal_in_body_[foot];
  const Eigen::VectorXd& u = pads_[foot]->displacement();
  compression = 0;
  displacement = 0;
  for (int k = 0; k < n_nodes(); ++k) {
    const Eigen::Vector3d u_k = pads_[foot]->node_to_world(k, u.segment<3>(3 * k));
    if (!u_k.allFinite()) { // the monitor treats NaN as past every limit
      compression = displacement = std::numeric_limits<double>::quiet_NaN();
      return;
    }
    compression = std::max(compression, u_k.dot(normal));
    displacement = std::max(displacement, u_k.norm());
  }
}

Eigen::Vector3d SolePatchFoot::node_force(int foot, int node) const {
  return pads_[foot]->node_force(node);
}

Eigen::Vector3d SolePatchFoot::node_force_world(int foot, int node) const {
  return pads_[foot]->node_to_world(node, pads_[foot]->node_force(node));
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
  out.torque.setZero();
  out.depth = 0;
  const coupling::PadState& pad = *pads_[foot];
  for (int k = 0; k < n_nodes(); ++k) {
    const Node& c = feet_[foot][k];
    const Eigen::Vector3d f = pad.node_to_world(k, pad.node_force(k));
    const Eigen::Vector3d x = data.oMi[c.body].act_point(c.position);
    out.force += f;
    out.moment.x() += f.z() * x.x();
    out.moment.y() += f.z() * x.y();
    out.torque += x.cross(f);
    // The deformed node's gap: the terrain's gap of the undeformed node plus U_n.
    double gap = contact::terrain_gap(stepper_->terrain(), x);
    gap += pad.displacement()[3 * k];
    out.depth = std::max(out.depth, -gap);
  }
}

void SolePatchFoot::write_fields(int foot, const multibody::SE3& placement,
                                 const std::filesystem::path& path) const {
  const SoleMesh mesh = sole_mesh(foot);
  const PadFieldMesh field_mesh{mesh.dof_handler, mesh.discretization, mesh.contact_dofs,
                                &node_areas(foot)};
  const std::unique_ptr<dealii::DataPostprocessor<3>> stress = stress_postprocessor(foot);
  write_pad_fields(
      field_mesh, *pads_[foot],
      [&](const Eigen::VectorXd& contact_u,
          dealii::Vector<double>& workspace) -> const dealii::Vector<double>& {
        return displacement_field(foot, contact_u, workspace);
      },
      *stress, placement, path, cell_fields(foot));
}

} // namespace plantar::app
