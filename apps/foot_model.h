#pragma once
// How the feet of a humanoid scene touch the ground: one interface, one implementation per
// foot form (rigid_foot.h, compliant_ankle_foot.h, condensed_sole_foot.h,
// hyperelastic_sole_foot.h), created by make_foot_model (foot_model_registry.h).
//
// HumanoidSimulation calls, in this order: configure_model (before the model is built),
// lift, plan (once the reference exists), max_contacts, attach (the stepper's contacts of
// both feet), set_reference_state (initial and planned final configurations, and the balance
// loop's reference before every step); then after every step
// update, check_validity and report; output writers ask has_fields / write_fields.

#include "apps/humanoid_summary.h"
#include "apps/validity_monitor.h"
#include "multibody/data.h"
#include "multibody/model.h"
#include "multibody/spatial.h"
#include "multibody/urdf_loader.h"

#include <Eigen/Core>

#include <limits>

#include <array>
#include <filesystem>

namespace plantar::multibody {
class Stepper;
}
namespace plantar::walking {
struct Humanoid;
struct JointReference;
} // namespace plantar::walking

namespace plantar::app {

/// One foot's contacts after a step (world frame).
struct FootReport {
  Eigen::Vector3d force = Eigen::Vector3d::Zero();  ///< N, sum of the contact forces
  Eigen::Vector3d moment = Eigen::Vector3d::Zero(); ///< (sum f_z x, sum f_z y, 0), N m
  /// sum x × f about the world origin, world axes, N m (x the contact point; a sole's node
  /// undeformed): the ground's moment on the foot, the F/T sensors' input.
  Eigen::Vector3d torque = Eigen::Vector3d::Zero();
  double depth = 0; ///< m, deepest contact point below z = 0 (deformed sole included)
};

class FootModel {
public:
  virtual ~FootModel() = default;

  /// Adds this form's parts of the robot (e.g. compliant ankle joints) to @p options.
  virtual void configure_model(multibody::ModelOptions& options) const { (void)options; }
  /// Lift of the robot above the reference (m, >= 0): what the form adds under the sole frames.
  virtual double lift() const { return 0.0; }
  /// Called once the joint reference (on the robot without this form's joints) exists; may
  /// adapt it (e.g. compensate the ankle springs' deflection).
  virtual void plan(const multibody::Model& reference_model, const walking::Humanoid& humanoid,
                    walking::JointReference& reference) {
    (void)reference_model, (void)humanoid, (void)reference;
  }
  /// Contact points of one foot, undeformed, in its sole frame (3 x n, m; the same for both
  /// feet): e.g. to place a dropped robot by its lowest point.
  virtual const Eigen::Matrix3Xd& contact_points() const = 0;
  /// Contact points of both feet together: the stepper's capacity.
  virtual int max_contacts() const = 0;
  /// Adds the contacts of both feet to @p stepper; @p sole_frames: model frames of the right
  /// (0) and left (1) sole; @p friction: Coulomb mu. The stepper and model must outlive this.
  void attach(multibody::Stepper& stepper, const multibody::Model& model,
              const std::array<int, 2>& sole_frames, double friction) {
    stepper_ = &stepper;
    model_ = &model;
    sole_frames_ = sole_frames;
    add_contacts(friction);
  }
  /// Sets this form's own coordinates of @p q (size model.nq) to the plan's at time @p t (s), so
  /// that the reference's soles are the planned feet: the initial state (t = 0), the planned
  /// soles at the end, and the balance loop's reference (its contact test, touchdown adaptation
  /// and anchors). No heap allocation.
  virtual void set_reference_state(double t, Eigen::Ref<Eigen::VectorXd> q) const {
    (void)t, (void)q;
  }
  /// After a step (@p data: kinematics of the step's end). No heap allocation. Throws
  /// std::runtime_error naming the foot on failure.
  virtual void update(const multibody::Data& data) { (void)data; }
  /// After update (@p data: kinematics of the step's end): reports each quantity that bounds
  /// this form's validity to @p monitor (apps/validity_monitor.h: a warning past its warning
  /// level, std::runtime_error naming the remedy past its failure level). No heap allocation
  /// unless it throws. Default: nothing to watch (rigid feet, ankle springs).
  virtual void check_validity(const multibody::Data& data, ValidityMonitor& monitor) const {
    (void)data, (void)monitor;
  }
  /// Contacts of foot @p foot (0 right, 1 left) after the step of @p dt (s). No heap allocation.
  virtual void report(int foot, const multibody::Data& data, double dt, FootReport& out) const = 0;
  /// The tilt stiffness (roll, pitch about the sole axes; N m/rad) of what lies between the foot
  /// link's ankle and a flat ground under the whole sole, the other motions free: infinite for
  /// a rigid foot (the default), the springs of a compliant ankle, the whole face of a sole.
  virtual Eigen::Vector2d tilt_stiffness() const {
    return Eigen::Vector2d::Constant(std::numeric_limits<double>::infinity());
  }
  /// Fills this form's figures of @p summary (contact nodes, sole statistics, foot_stiffness).
  virtual void summarize(HumanoidSummary& summary) const { (void)summary; }
  /// Whether write_fields writes anything (a field per sole).
  virtual bool has_fields() const { return false; }
  /// Writes the fields of foot @p foot as a .vtu at @p path, the sole frame at @p placement
  /// (world). Allocates (output steps only).
  virtual void write_fields(int foot, const multibody::SE3& placement,
                            const std::filesystem::path& path) const {
    (void)foot, (void)placement, (void)path;
  }

  /// Model frame of the right (0) or left (1) sole; valid after attach.
  int sole_frame(int foot) const { return sole_frames_[foot]; }

protected:
  /// attach's own part: the contacts of both feet.
  virtual void add_contacts(double friction) = 0;

  multibody::Stepper* stepper_ = nullptr;
  const multibody::Model* model_ = nullptr;
  std::array<int, 2> sole_frames_{};
};

} // namespace plantar::app
