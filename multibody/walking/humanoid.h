// A humanoid robot as its scene names it (base link, legs, soles, controlled joints, posture),
// resolved once against a multibody::Model. No robot's names in code: everything here comes
// from the scene's subsection Robot.
#pragma once

#include "multibody/model.h"
#include "multibody/spatial.h"

#include <Eigen/Core>

#include <array>
#include <string>
#include <utility>
#include <vector>

namespace plantar::walking {

enum class LegSide { right, left };
constexpr std::array<LegSide, 2> leg_sides = {LegSide::right, LegSide::left};
/// "right" or "left".
const char* to_string(LegSide side);

/// The robot-specific names of a humanoid, as written in a scene (strings only).
struct HumanoidDescription {
  /// Link of the free-floating base (the waist): the root of both legs.
  std::string base_link;
  /// Right and left foot link: the last link of each leg; the chain of actuated 1-DoF joints
  /// from base_link down to it is the leg and must have 6 joints.
  std::array<std::string, 2> foot_links;
  /// Sole frame of each foot (origin at the centre of the sole's bottom face, z up, x
  /// forward): a link of the URDF, or empty to use sole_placements on the foot link.
  std::array<std::string, 2> sole_frames;
  /// Sole frame -> foot link frame, used where sole_frames is empty.
  std::array<multibody::SE3, 2> sole_placements;
  /// Joints the reference drives (its columns, in this order); empty: every actuated 1-DoF joint
  /// in model order. Must contain both legs.
  std::vector<std::string> controlled_joints;
  /// Standing posture: (joint name, angle [rad] or displacement [m]); joints not named are at 0;
  /// the legs' angles are set by the inverse kinematics.
  std::vector<std::pair<std::string, double>> posture;
};

/// A HumanoidDescription resolved against one Model: indices only (constant after
/// construction). Frames named by placement are added to the model by add_sole_frames().
struct Humanoid {
  /// Resolves @p description in @p model. Throws std::invalid_argument naming the entry
  /// (e.g. "right foot link = 'X'") and what is wrong: an unknown link, frame or joint, a
  /// leg whose chain from the base does not have exactly 6 actuated 1-DoF joints, legs that
  /// share a joint, a sole frame not below its leg, a leg joint that is not controlled, a
  /// posture joint that is not controlled.
  Humanoid(const multibody::Model& model, const HumanoidDescription& description);

  int base_body = 1;                              ///< model body of the base link
  std::vector<int> joints;                        ///< model joint ids of the controlled joints
  std::vector<std::string> joint_names;           ///< their names (reference and CSV column order)
  std::array<std::array<int, 6>, 2> leg_joints{}; ///< model joint ids, hip first, per leg
  /// Columns of each leg's joints in the controlled-joint vector (same order as leg_joints).
  std::array<std::array<int, 6>, 2> leg_columns{};
  std::array<int, 2> foot_frames{}; ///< model frame of each foot link
  std::array<int, 2> sole_frames{}; ///< model frame of each sole
  Eigen::VectorXd posture;          ///< standing posture per controlled joint (legs: 0)

  int n_joints() const { return static_cast<int>(joints.size()); }

  /// Writes the controlled-joint vector @p angles (n_joints) into the configuration @p q (nq).
  void to_configuration(const multibody::Model& model,
                        const Eigen::Ref<const Eigen::VectorXd>& angles,
                        Eigen::Ref<Eigen::VectorXd> q) const;
};

/// Name of the frame add_sole_frames() adds for a sole given by placement: "<foot link>_sole".
std::string placed_sole_frame_name(const HumanoidDescription& description, LegSide side);

/// Adds a frame for each sole given by a placement (sole_frames[i] empty) on its foot link.
/// Call before the model is used. Throws std::invalid_argument for an unknown foot link or a
/// frame name already taken.
void add_sole_frames(multibody::Model& model, const HumanoidDescription& description);

} // namespace plantar::walking
