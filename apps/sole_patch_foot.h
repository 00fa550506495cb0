#pragma once
// The common part of the FEM-sole foot forms (condensed_sole_foot.h, hyperelastic_sole_foot.h):
// each foot carries one compliant patch of the stepper (the sole's contact nodes with their
// condensed compliance, paper eq. 12), and the sole's fields are written as a .vtu.
// The only user of the stepper's patch API in apps/.

#include "apps/foot_model.h"
#include "apps/pad_field_writer.h"
#include "coupling/pad_state.h"
#include "fem/discretization.h"
#include "fem/mesh_import.h"
#include "fem/sole_parameters.h"

#include <deal.II/dofs/dof_handler.h>
#include <deal.II/grid/tria.h>
#include <deal.II/lac/vector.h>
#include <deal.II/numerics/data_postprocessor.h>

#include <memory>
#include <vector>

namespace plantar::app {

class SolePatchFoot : public FootModel {
public:
  /// The contact nodes (the bottom face, z = -thickness, or the reduced patches' centres).
  const Eigen::Matrix3Xd& contact_points() const override { return nodes_; }
  int max_contacts() const override { return 2 * n_nodes(); }
  /// Force: the node forces at the step's end; depth: of the deformed nodes (z + u_n).
  void report(int foot, const multibody::Data& data, double dt, FootReport& out) const override;
  /// The contact face's tilt stiffness, k = 1 / [K_R^-1]_theta,theta with K_R = R^T C^-1 R the
  /// face's stiffness against rigid motions (coupling/reduced_sole.h; every node stuck to the
  /// ground, the translations and the other rotations free); at u = 0. A dense solve with the
  /// 3n x 3n compliance: call it once, at setup.
  Eigen::Vector2d tilt_stiffness() const override;
  /// Contact nodes per sole and the sole's vertical stiffness (foot_stiffness, at u = 0).
  void summarize(HumanoidSummary& summary) const override;
  /// The .vtu of scene_vtk_writer.h: displacement (world), stress fields, contact
  /// displacement, force, pressure and node flag, material ids.
  void write_fields(int foot, const multibody::SE3& placement,
                    const std::filesystem::path& path) const override;

  /// The pad state (node forces and displacements) of foot @p foot (0 right, 1 left).
  const coupling::PadState& pad(int foot) const { return *pads_[foot]; }

protected:
  /// Meshes the sole of @p sole into @p tria (the top and bottom surfaces named).
  static fem::PhysicalGroups mesh_sole(const fem::SoleParameters& sole,
                                       dealii::Triangulation<3>& tria);
  /// The patch of each foot (before attach): @p nodes 3 x n contact nodes (sole frame, m),
  /// @p compliance 3n x 3n (sole frame, m/N), @p damping_time Kelvin-Voigt beta (s).
  void set_patch(Eigen::Matrix3Xd nodes, Eigen::MatrixXd compliance, double damping_time);
  void add_contacts(double friction) override;
  int n_nodes() const { return static_cast<int>(nodes_.cols()); }
  /// The stepper's pad state of foot @p foot (valid after attach).
  coupling::PadState& pad_state(int foot) { return *pads_[foot]; }
  /// Force on node @p node of foot @p foot at the step's end, in the node's contact frame
  /// (n, t1, t2) (on flat ground world (z, x, y)), N.
  Eigen::Vector3d node_force(int foot, int node) const;
  /// The same force in world components, N.
  Eigen::Vector3d node_force_world(int foot, int node) const;
  /// Largest compression u_k . n (m; n: the sole's normal into the foot) and largest |u_k|
  /// (m) over the contact nodes of foot @p foot after the step (@p data: its kinematics).
  /// No heap allocation.
  void node_deformation(int foot, const multibody::Data& data, double& compression,
                        double& displacement) const;
  /// Replaces foot @p foot's patch compliance (3n x 3n, m/N) and offset (3n, m), body frame.
  void set_patch_compliance(int foot, const Eigen::MatrixXd& compliance,
                            const Eigen::VectorXd& offset);

  /// A sole's mesh for output.
  struct SoleMesh {
    const dealii::DoFHandler<3>* dof_handler = nullptr;
    const fem::Discretization* discretization = nullptr;
    /// x, y, z dofs of each contact node, in the patch's node order.
    const std::vector<std::array<dealii::types::global_dof_index, 3>>* contact_dofs = nullptr;
  };
  virtual SoleMesh sole_mesh(int foot) const = 0;
  /// Consistent areas a_k = int_bottom N_k ds of the contact nodes (m^2, n).
  virtual const Eigen::VectorXd& node_areas(int foot) const = 0;
  /// The displacement field of foot @p foot (sole frame), given its contact displacements
  /// @p contact_u (3n, sole frame); may use @p workspace.
  virtual const dealii::Vector<double>&
  displacement_field(int foot, const Eigen::VectorXd& contact_u,
                     dealii::Vector<double>& workspace) const = 0;
  /// Strain, stress and von Mises stress of foot @p foot's material.
  virtual std::unique_ptr<dealii::DataPostprocessor<3>> stress_postprocessor(int foot) const = 0;
  /// More per-cell fields of foot @p foot's .vtu (none by default).
  virtual std::vector<PadCellField> cell_fields(int foot) const {
    (void)foot;
    return {};
  }

private:
  struct Node {
    int body = 0;
    Eigen::Vector3d position; ///< body coordinates, m
  };
  Eigen::Matrix3Xd nodes_;
  Eigen::MatrixXd compliance_;
  double damping_time_ = 0;
  double stiffness_ = 0;                                    ///< N/m, 1^T C_zz^-1 1 of compliance_
  std::array<std::unique_ptr<coupling::PadState>, 2> pads_; ///< the stepper's patches
  std::array<std::vector<Node>, 2> feet_;
  std::array<int, 2> bodies_{};                   ///< the body carrying each sole
  std::array<Eigen::Vector3d, 2> normal_in_body_; ///< each sole's normal (into the foot), body
};

} // namespace plantar::app
