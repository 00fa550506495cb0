#pragma once
// Foot form "fem sole" with Sole/Model = hyperelastic: one hyperelastic sole per foot
// (coupling/nonlinear_condensed_sole.h, laws of Sole/Materials), its tangent condensed onto
// the bottom nodes as the foot's compliant patch and re-condensed after the steps whose
// contact forces moved the prediction beyond Sole/Recondensation tolerance. The robot is
// lifted by Sole/Thickness. Validity: J = det F (min over the quadrature points of both soles
// at their last Newton solve) against Sole/Jacobian warning and Min jacobian; a Newton solve
// that fails stops the run naming the remedies (smaller dt, finer mesh, mixed formulation).
// Viscous branches in Sole/Materials (beta<i>/G<i>, tau<i>: visco-hyperelasticity,
// fem/visco_hyperelastic_law.h): the soles' internal variables advance with the time loop
// (coupling/nonlinear_condensed_sole.h: Newton checks on force change and on creep, the offset
// d following the creep between them); Sole/Damping time must then be 0. The summary's
// sole_dissipated_energy is then the dashpots' dissipation of both feet
// (ViscoHyperelasticLaw::commit, integrated over the intervals between Newton checks), and the
// .vtu series gains per cell dissipated_energy_density (J/m^3) and overstress_<i> (|Q_i|, Pa).

#include "apps/sole_patch_foot.h"

namespace plantar::coupling {
class NonlinearCondensedSole;
}

namespace plantar::app {

struct Scene;

class HyperelasticSoleFoot : public SolePatchFoot {
public:
  /// Meshes the sole of @p scene and builds both feet's soles. Throws std::invalid_argument
  /// for a reduced sole (Sole/Reduced patches).
  explicit HyperelasticSoleFoot(const Scene& scene);
  ~HyperelasticSoleFoot() override;
  double lift() const override { return thickness_; }
  /// Contact forces -> each sole; re-condensed tangents -> the stepper. Throws
  /// std::runtime_error "<foot> hyperelastic sole: ..." with the remedies if a sole's Newton
  /// solve fails.
  void update(const multibody::Data& data) override;
  /// min J of both soles against its limits.
  void check_validity(const multibody::Data& data, ValidityMonitor& monitor) const override;
  void summarize(HumanoidSummary& summary) const override;
  bool has_fields() const override { return true; }
  /// The sole of foot @p foot (0 right, 1 left).
  const coupling::NonlinearCondensedSole& sole(int foot) const { return *soles_[foot]; }

protected:
  SoleMesh sole_mesh(int foot) const override;
  const Eigen::VectorXd& node_areas(int foot) const override;
  /// The sole's full field at its last Newton check (the writer solves nothing).
  const dealii::Vector<double>&
  displacement_field(int foot, const Eigen::VectorXd& contact_u,
                     dealii::Vector<double>& workspace) const override;
  std::unique_ptr<dealii::DataPostprocessor<3>> stress_postprocessor(int foot) const override;
  /// Viscous soles: dissipated_energy_density and overstress_<i> per cell (none otherwise).
  std::vector<PadCellField> cell_fields(int foot) const override;

private:
  double thickness_ = 0;
  bool viscous_ = false; ///< Sole/Materials has viscous branches
  ValidityLimit jacobian_limit_;
  std::array<std::unique_ptr<coupling::NonlinearCondensedSole>, 2> soles_;
  Eigen::VectorXd forces_, offset_; ///< 3 n_c workspaces of update()
  Eigen::MatrixXd compliance_;      ///< 3 n_c square workspace of update()
  mutable Eigen::VectorXd area_;    ///< node_areas, computed at the first call
};

} // namespace plantar::app
