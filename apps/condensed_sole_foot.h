#pragma once
// Foot form "fem sole" with Sole/Model = linear: the linear FEM sole of subsection Sole,
// condensed onto its bottom nodes (coupling/condensed_sole.h, paper eq. 11), one compliant
// patch per foot; with Sole/Reduced patches the reduced sole (coupling/reduced_sole.h: one
// contact per patch of bottom nodes), its grid given or chosen (auto) by its reduction error
// estimate against Sole/Reduction tolerance, built from the kept factorization of K without the
// dense C; its fields are recovered from the patch forces (write_fields). The robot is lifted by
// Sole/Thickness. Validity (small strains): each node's compression and displacement against the
// thickness, Sole/Compression warning, Max compression, Strain warning, Max strain
// (SoleValidityParameters; for the reduced sole the patches' averaged displacements).

#include "apps/sole_patch_foot.h"

#include <Eigen/Cholesky>

namespace plantar::coupling {
class CondensedSole;
class ReducedSole;
} // namespace plantar::coupling

namespace plantar::app {

struct Scene;

class CondensedSoleFoot : public SolePatchFoot {
public:
  /// Meshes and condenses the sole of @p scene (the long part of a run's set-up).
  explicit CondensedSoleFoot(const Scene& scene);
  ~CondensedSoleFoot() override;
  double lift() const override { return thickness_; }
  /// The sole's contacts and stiffness (SolePatchFoot) and the reduction's grid and estimate.
  void summarize(HumanoidSummary& summary) const override;
  /// Compression and strain of each sole against its limits.
  void check_validity(const multibody::Data& data, ValidityMonitor& monitor) const override;
  /// The full sole's, or the reduced sole's while its factorization is kept (Output/Write VTU).
  bool has_fields() const override;
  /// The full sole's fields (SolePatchFoot), or the reduced sole's: the field of the patch
  /// forces F_e = C_r^-1 U that give the patch displacements U, each shared by the patch's
  /// nodes (f = A F_e, u = K^-1 B f: A^T u_c = U); contact forces A F.
  void write_fields(int foot, const multibody::SE3& placement,
                    const std::filesystem::path& path) const override;
  /// The condensed sole (both feet; Form::factorization when reduced).
  const coupling::CondensedSole* sole() const { return sole_.get(); }
  /// The reduced sole, or nullptr.
  const coupling::ReducedSole* reduced() const { return reduced_.get(); }

protected:
  SoleMesh sole_mesh(int foot) const override;
  const Eigen::VectorXd& node_areas(int foot) const override;
  const dealii::Vector<double>&
  displacement_field(int foot, const Eigen::VectorXd& contact_u,
                     dealii::Vector<double>& workspace) const override;
  std::unique_ptr<dealii::DataPostprocessor<3>> stress_postprocessor(int foot) const override;

private:
  double thickness_ = 0;
  ValidityLimit compression_limit_, strain_limit_;
  std::unique_ptr<coupling::CondensedSole> sole_;
  std::unique_ptr<coupling::ReducedSole> reduced_;
  std::unique_ptr<Eigen::LDLT<Eigen::MatrixXd>> reduced_factor_; ///< of C_r, for write_fields
  mutable dealii::Vector<double> field_;                         ///< write_fields' field
  mutable Eigen::VectorXd area_;          ///< node_areas, computed at the first call
  int reduction_x_ = 0, reduction_y_ = 0; ///< the reduced sole's grid (0: full)
  double reduction_estimate_ = 0;         ///< coupling::reduction_error_estimate
  double pressure_estimate_ = 0;          ///< coupling::pressure_error_estimate
  bool reduction_reached_ = true;         ///< auto: a reduced grid met the tolerance
};

} // namespace plantar::app
