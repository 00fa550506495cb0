#pragma once
// The deformable pads of a humanoid scene (subsections Pad 1 ... Pad 6, apps/pad_parameters.h)
// in the time loop: each pad is one compliant patch of the stepper on the body that carries its
// link, with its state (coupling::PadState). An elastic pad (coupling::DeformablePad) is
// condensed once; a viscoelastic one (law=prony in its materials: coupling::ViscoelasticPad) is
// condensed once at the scene's dt and renews its history offset after every step
// (finish_step). After each step the set reports each pad's force and compression and checks
// the linear model's validity; output writers ask for each pad's .vtu (apps/pad_field_writer.h).

#include "apps/pad_parameters.h"
#include "contact/terrain.h"
#include "coupling/deformable_pad.h"
#include "coupling/pad_state.h"
#include "coupling/viscoelastic_pad.h"
#include "multibody/data.h"
#include "multibody/model.h"

#include <Eigen/Core>

#include <filesystem>
#include <memory>
#include <vector>

namespace plantar::multibody {
class Stepper;
}

namespace plantar::app {

/// One pad's contacts after a step (world frame).
struct PadReport {
  Eigen::Vector3d force = Eigen::Vector3d::Zero(); ///< N, sum of the node forces on the pad
  double depth = 0;       ///< m, deepest deformed contact node below z = 0 (0 if none)
  double compression = 0; ///< m, max over the nodes of the displacement into the pad, u . R e_z
};

class PadSet {
public:
  /// Builds (meshes and condenses) every pad of @p entries; a viscoelastic pad at the time step
  /// @p time_step (s, > 0: the stepper's), with its per-cell dissipation accumulated when
  /// @p cell_dissipation (the .vtu field; else a separable pad runs in contact space,
  /// fem/viscoelastic_condensation.h). Throws what DeformablePad or ViscoelasticPad throws,
  /// prefixed with the pad's name.
  PadSet(const std::vector<PadEntry>& entries, double time_step, bool cell_dissipation);
  ~PadSet();
  PadSet(const PadSet&) = delete;
  PadSet& operator=(const PadSet&) = delete;

  int size() const { return static_cast<int>(entries_.size()); }
  const PadEntry& entry(int i) const { return entries_[i]; }
  const std::string& name(int i) const { return entries_[i].description.name; }
  /// Pad @p i's elastic model, nullptr for a viscoelastic pad.
  const coupling::DeformablePad* elastic(int i) const { return elastic_[i].get(); }
  /// Pad @p i's viscoelastic model, nullptr for an elastic pad.
  const coupling::ViscoelasticPad* viscoelastic(int i) const { return viscoelastic_[i].get(); }
  /// Extent of pad @p i's mesh along its z (m).
  double thickness(int i) const { return thickness_[i]; }
  /// Contact nodes of all pads together: their part of the stepper's capacity.
  int max_contacts() const;

  /// Resolves each pad's link in @p model (a URDF link, possibly merged into a body by fixed
  /// joints). Throws std::invalid_argument "Pad <name>/Link = '<link>': ..." for an unknown
  /// link or the world. Before lowest_point() and attach().
  void resolve(const multibody::Model& model);
  /// The lowest undeformed contact node over all pads at the kinematics @p data: the least
  /// height above @p terrain, min_k (z_k - h(x_k, y_k)) (m); +infinity without pads.
  double lowest_point(const multibody::Data& data, const contact::Terrain& terrain) const;
  /// Adds each pad as a deformable patch of @p stepper (which must outlive this set).
  void attach(multibody::Stepper& stepper);

  /// After each step of the stepper: the viscoelastic pads advance their FEM state under the
  /// step's node forces and set their next history offset (coupling::ViscoelasticPad::
  /// finish_step). No heap allocation. Throws std::runtime_error naming the pad on failure.
  void finish_step();
  /// Energy dissipated so far by the viscoelastic pads (J, sum over the pads).
  double dissipated_energy() const;

  /// Pad @p i after the step (@p data: the step's end). No heap allocation.
  void report(int i, const multibody::Data& data, PadReport& out) const;
  /// Throws std::runtime_error naming the pad if @p report's compression exceeds its
  /// Max compression times its thickness.
  void check(int i, const PadReport& report) const;
  /// Pad @p i's fields (.vtu at @p path, world placement from @p data). Allocates.
  void write_fields(int i, const multibody::Data& data, const std::filesystem::path& path) const;

  /// Pad @p i's state in the time loop (node forces and displacements); valid after attach.
  const coupling::PadState& state(int i) const { return *states_[i]; }

private:
  /// Pad frame -> world at @p data.
  multibody::SE3 placement(int i, const multibody::Data& data) const;

  std::vector<PadEntry> entries_;
  std::vector<std::unique_ptr<coupling::DeformablePad>> elastic_;        ///< null if viscoelastic
  std::vector<std::unique_ptr<coupling::ViscoelasticPad>> viscoelastic_; ///< null if elastic
  std::vector<double> thickness_;                                        ///< m
  std::vector<Eigen::Matrix3Xd> link_nodes_; ///< contact nodes in link coordinates (3 x n), m
  std::vector<std::unique_ptr<coupling::PadState>> states_;
  std::vector<int> bodies_;                   ///< the body carrying each pad
  std::vector<multibody::SE3> link_in_body_;  ///< each pad's link frame -> body frame
  std::vector<Eigen::Matrix3Xd> body_nodes_;  ///< contact nodes in body coordinates (3 x n), m
  std::vector<Eigen::VectorXd> areas_;        ///< consistent node areas (m^2), for the .vtu
  const contact::Terrain* terrain_ = nullptr; ///< the stepper's ground (attach)
};

} // namespace plantar::app
