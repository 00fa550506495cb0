#include "apps/pad_set.h"

#include "apps/pad_field_writer.h"
#include "contact/ground_frame.h"
#include "coupling/contact_frame_compliance.h"
#include "fem/field_output.h"
#include "multibody/stepper.h"

#include <limits>
#include <sstream>
#include <stdexcept>

namespace plantar::app {

PadSet::PadSet(const std::vector<PadEntry>& entries) : entries_(entries) {
  for (const PadEntry& entry : entries_) {
    try {
      pads_.push_back(std::make_unique<coupling::DeformablePad>(entry.description));
    } catch (const std::invalid_argument& e) {
      throw std::invalid_argument("pad " + entry.description.name + ": " + e.what());
    } catch (const std::exception& e) {
      throw std::runtime_error("pad " + entry.description.name + ": " + e.what());
    }
    const coupling::CondensedSole& condensed = pads_.back()->condensed();
    const int n = condensed.n_contacts();
    Eigen::VectorXd unit_load(3 * n);
    condensed.contact_load(Eigen::Vector3d(0, 0, 1), unit_load);
    Eigen::VectorXd area(n);
    for (int k = 0; k < n; ++k)
      area[k] = unit_load[3 * k + 2];
    areas_.push_back(std::move(area));
  }
}

PadSet::~PadSet() = default;

int PadSet::max_contacts() const {
  int n = 0;
  for (const auto& pad : pads_)
    n += pad->n_contacts();
  return n;
}

void PadSet::resolve(const multibody::Model& model) {
  bodies_.clear();
  link_in_body_.clear();
  body_nodes_.clear();
  for (const auto& pad : pads_) {
    int frame = -1;
    try {
      frame = model.frame_id(pad->link());
    } catch (const std::invalid_argument&) {
      throw std::invalid_argument("Pad " + pad->name() + "/Link = '" + pad->link() +
                                  "': not a link of the robot");
    }
    const multibody::Frame& link = model.frames[frame];
    if (link.body == 0)
      throw std::invalid_argument("Pad " + pad->name() + "/Link = '" + pad->link() +
                                  "': fixed to the world, not to a moving link");
    bodies_.push_back(link.body);
    link_in_body_.push_back(link.placement);
    const Eigen::Matrix3Xd& nodes = pad->contact_positions();
    Eigen::Matrix3Xd body_nodes(3, nodes.cols());
    for (Eigen::Index k = 0; k < nodes.cols(); ++k)
      body_nodes.col(k) = link.placement.act_point(nodes.col(k));
    body_nodes_.push_back(std::move(body_nodes));
  }
}

double PadSet::lowest_point(const multibody::Data& data) const {
  double lowest = std::numeric_limits<double>::infinity();
  for (int i = 0; i < size(); ++i)
    for (Eigen::Index k = 0; k < body_nodes_[i].cols(); ++k)
      lowest = std::min(lowest, data.oMi[bodies_[i]].act_point(body_nodes_[i].col(k)).z());
  return lowest;
}

void PadSet::attach(multibody::Stepper& stepper) {
  if (static_cast<int>(bodies_.size()) != size())
    throw std::logic_error("PadSet::attach before resolve");
  states_.clear();
  for (int i = 0; i < size(); ++i) {
    const coupling::DeformablePad& pad = *pads_[i];
    Eigen::MatrixXd compliance(pad.compliance().rows(), pad.compliance().cols());
    coupling::rotate_compliance(link_in_body_[i].rotation, pad.compliance(), compliance);
    states_.push_back(std::make_unique<coupling::PadState>(compliance));
    stepper.add_deformable_patch(bodies_[i], body_nodes_[i], pad.friction(), *states_.back());
    states_.back()->set_damping(entries_[i].damping_time);
  }
}

multibody::SE3 PadSet::placement(int i, const multibody::Data& data) const {
  const coupling::DeformablePad& pad = *pads_[i];
  const multibody::SE3 pad_in_link(pad.rotation(), pad.description().translation);
  return data.oMi[bodies_[i]] * (link_in_body_[i] * pad_in_link);
}

void PadSet::report(int i, const multibody::Data& data, PadReport& out) const {
  const coupling::PadState& state = *states_[i];
  const Eigen::Matrix3d& body_rotation = data.oMi[bodies_[i]].rotation;
  // The pad's z axis in the world: u . R e_z > 0 pushes a bottom node into the pad.
  const Eigen::Vector3d inward =
      body_rotation * link_in_body_[i].rotation * pads_[i]->rotation().col(2);
  out.force.setZero();
  out.depth = 0;
  out.compression = 0;
  const Eigen::VectorXd& u = state.displacement();
  for (int k = 0; k < state.n_nodes(); ++k) {
    out.force += contact::ground_to_world(state.node_force(k));
    const Eigen::Vector3d displacement = contact::ground_to_world(u.segment<3>(3 * k));
    const Eigen::Vector3d x = data.oMi[bodies_[i]].act_point(body_nodes_[i].col(k));
    out.depth = std::max(out.depth, -(x.z() + displacement.z()));
    out.compression = std::max(out.compression, displacement.dot(inward));
  }
}

void PadSet::check(int i, const PadReport& report) const {
  const double limit = entries_[i].max_compression * pads_[i]->thickness();
  if (report.compression > limit) {
    std::ostringstream msg;
    msg << "pad " << pads_[i]->name() << " compressed by " << report.compression
        << " m, more than Max compression " << entries_[i].max_compression << " x its thickness "
        << pads_[i]->thickness() << " m: past the linear pad's validity";
    throw std::runtime_error(msg.str());
  }
}

void PadSet::write_fields(int i, const multibody::Data& data,
                          const std::filesystem::path& path) const {
  const coupling::CondensedSole& condensed = pads_[i]->condensed();
  const PadFieldMesh mesh{&condensed.elasticity().dof_handler(),
                          &condensed.elasticity().discretization(), &condensed.contact_dofs(),
                          &areas_[i]};
  const fem::StressPostprocessor stress(condensed.elasticity().materials());
  write_pad_fields(
      mesh, *states_[i],
      [&](const Eigen::VectorXd& contact_u,
          dealii::Vector<double>& workspace) -> const dealii::Vector<double>& {
        condensed.recover(contact_u, workspace);
        return workspace;
      },
      stress, placement(i, data), path);
}

} // namespace plantar::app
