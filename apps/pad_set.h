#pragma once
// The deformable pads of a humanoid scene (subsections Pad 1 ... Pad 6, apps/pad_parameters.h)
// in the time loop: each pad (coupling::DeformablePad, condensed once) is one compliant patch of
// the stepper on the body that carries its link, with its state (coupling::PadState); after
// each step the set reports each pad's force and compression and checks the linear model's
// validity; output writers ask for each pad's .vtu (apps/pad_field_writer.h).

#include "apps/pad_parameters.h"
#include "coupling/deformable_pad.h"
#include "coupling/pad_state.h"
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
  /// Builds (meshes and condenses) every pad of @p entries. Throws what DeformablePad throws,
  /// prefixed with the pad's name.
  explicit PadSet(const std::vector<PadEntry>& entries);
  ~PadSet();
  PadSet(const PadSet&) = delete;
  PadSet& operator=(const PadSet&) = delete;

  int size() const { return static_cast<int>(pads_.size()); }
  const coupling::DeformablePad& pad(int i) const { return *pads_[i]; }
  const PadEntry& entry(int i) const { return entries_[i]; }
  /// Contact nodes of all pads together: their part of the stepper's capacity.
  int max_contacts() const;

  /// Resolves each pad's link in @p model (a URDF link, possibly merged into a body by fixed
  /// joints). Throws std::invalid_argument "Pad <name>/Link = '<link>': ..." for an unknown
  /// link or the world. Before lowest_point() and attach().
  void resolve(const multibody::Model& model);
  /// The lowest undeformed contact node over all pads (world z, m) at the kinematics @p data;
  /// +infinity without pads.
  double lowest_point(const multibody::Data& data) const;
  /// Adds each pad as a deformable patch of @p stepper (which must outlive this set).
  void attach(multibody::Stepper& stepper);

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
  std::vector<std::unique_ptr<coupling::DeformablePad>> pads_;
  std::vector<std::unique_ptr<coupling::PadState>> states_;
  std::vector<int> bodies_;                  ///< the body carrying each pad
  std::vector<multibody::SE3> link_in_body_; ///< each pad's link frame -> body frame
  std::vector<Eigen::Matrix3Xd> body_nodes_; ///< contact nodes in body coordinates (3 x n), m
  std::vector<Eigen::VectorXd> areas_;       ///< consistent node areas (m^2), for the .vtu
};

} // namespace plantar::app
