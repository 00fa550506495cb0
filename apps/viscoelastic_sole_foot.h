#pragma once
// Foot form "fem sole" with Sole/Model = linear and a viscoelastic material (law=prony in
// Sole/Materials, fem/viscoelastic_material.h): one viscoelastic sole per foot
// (coupling/viscoelastic_pad.h), its effective compliance C_eff(dt) condensed once onto the
// bottom nodes as the foot's compliant patch, U = C_eff F + d, the history displacement d
// renewed after every step (exact: fem/viscoelastic_condensation.h). The robot is lifted by
// Sole/Thickness. Not combined with a reduced sole (Sole/Reduced patches) nor with the
// Kelvin-Voigt Sole/Damping time: both are refused with a message naming the parameter.

#include "apps/sole_patch_foot.h"

namespace plantar::coupling {
class ViscoelasticPad;
}

namespace plantar::app {

struct Scene;

/// Whether @p materials (the text of Sole/Materials) gives a region the law "prony".
bool has_viscoelastic_material(const std::string& materials);

class ViscoelasticSoleFoot : public SolePatchFoot {
public:
  /// Meshes the sole of @p scene and builds both feet's soles at dt = Simulation/Time step.
  /// Throws std::invalid_argument naming Sole/Reduced patches or Sole/Damping time if set.
  explicit ViscoelasticSoleFoot(const Scene& scene);
  ~ViscoelasticSoleFoot() override;
  double lift() const override { return thickness_; }
  /// After every step: each sole advanced under its node forces, its next offset d set on
  /// the foot's pad state. No heap allocation.
  void update(const multibody::Data& data) override;
  /// Contact nodes and the energy dissipated by both soles (HumanoidSummary).
  void summarize(HumanoidSummary& summary) const override;
  bool has_fields() const override { return true; }
  /// The sole of foot @p foot (0 right, 1 left).
  const coupling::ViscoelasticPad& sole(int foot) const { return *soles_[foot]; }

protected:
  void add_contacts(double friction) override;
  SoleMesh sole_mesh(int foot) const override;
  const Eigen::VectorXd& node_areas(int foot) const override;
  /// The sole's full field at the end of the last step (the writer solves nothing).
  const dealii::Vector<double>&
  displacement_field(int foot, const Eigen::VectorXd& contact_u,
                     dealii::Vector<double>& workspace) const override;
  /// Strain eps = sym grad u only: the stress depends on the history (a cell field).
  std::unique_ptr<dealii::DataPostprocessor<3>> stress_postprocessor(int foot) const override;
  /// dissipated_energy_density (J/m^3), von_mises (Pa, of the cell-mean stress),
  /// overstress_<i> (Pa, cell-mean |h_i| of branch i = 1..N).
  std::vector<PadCellField> cell_fields(int foot) const override;

private:
  double thickness_ = 0;
  dealii::types::boundary_id bottom_ = 0;
  std::array<std::unique_ptr<coupling::ViscoelasticPad>, 2> soles_;
  mutable Eigen::VectorXd area_; ///< node_areas, computed at the first call
};

} // namespace plantar::app
