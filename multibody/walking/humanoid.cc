#include "multibody/walking/humanoid.h"

#include <algorithm>
#include <sstream>
#include <stdexcept>

namespace plantar::walking {
namespace {

bool is_one_dof(const multibody::Model& model, int joint) {
  return model.joint_type[joint] == multibody::JointType::Revolute ||
         model.joint_type[joint] == multibody::JointType::Prismatic;
}

int find_frame(const multibody::Model& model, const std::string& name, const std::string& what) {
  for (size_t f = 0; f < model.frames.size(); ++f)
    if (model.frames[f].name == name)
      return static_cast<int>(f);
  throw std::invalid_argument(what + " = '" + name + "': no such link in the URDF");
}

} // namespace

const char* to_string(LegSide side) {
  return side == LegSide::right ? "right" : "left";
}

std::string placed_sole_frame_name(const HumanoidDescription& description, LegSide side) {
  return description.foot_links[static_cast<int>(side)] + "_sole";
}

void add_sole_frames(multibody::Model& model, const HumanoidDescription& description) {
  for (LegSide side : leg_sides) {
    const int i = static_cast<int>(side);
    if (!description.sole_frames[i].empty())
      continue;
    const std::string name = placed_sole_frame_name(description, side);
    const int foot =
        find_frame(model, description.foot_links[i], std::string(to_string(side)) + " foot link");
    for (const multibody::Frame& frame : model.frames)
      if (frame.name == name)
        throw std::invalid_argument("sole frame '" + name + "' of the " + to_string(side) +
                                    " foot: the model already has a frame of that name");
    const multibody::Frame& foot_frame = model.frames[foot];
    model.frames.push_back(
        {name, foot_frame.body, foot_frame.placement * description.sole_placements[i]});
  }
}

Humanoid::Humanoid(const multibody::Model& model, const HumanoidDescription& description) {
  const multibody::Frame& base =
      model.frames[find_frame(model, description.base_link, "base link")];
  if (!base.placement.translation.isZero(0.0) || !base.placement.rotation.isIdentity(0.0))
    throw std::invalid_argument("base link = '" + description.base_link +
                                "': not the root link of its body (a fixed joint joins it to '" +
                                model.body_names[base.body] + "'); name the body's root link");
  base_body = base.body;

  // Controlled joints.
  if (description.controlled_joints.empty()) {
    for (int j = 1; j < model.n_bodies; ++j)
      if (is_one_dof(model, j) && model.actuated[model.idx_v[j]])
        joints.push_back(j);
  } else {
    for (const std::string& name : description.controlled_joints) {
      const auto it = std::find(model.joint_names.begin(), model.joint_names.end(), name);
      if (it == model.joint_names.end())
        throw std::invalid_argument("controlled joint '" + name + "': no such joint in the URDF");
      const int j = static_cast<int>(it - model.joint_names.begin());
      if (!is_one_dof(model, j) || !model.actuated[model.idx_v[j]])
        throw std::invalid_argument("controlled joint '" + name +
                                    "' is not an actuated revolute or prismatic joint");
      if (std::find(joints.begin(), joints.end(), j) != joints.end())
        throw std::invalid_argument("controlled joint '" + name + "' is listed twice");
      joints.push_back(j);
    }
  }
  for (int j : joints)
    joint_names.push_back(model.joint_names[j]);

  // Legs: the actuated 1-DoF joints from the base body down to each foot link.
  for (LegSide side : leg_sides) {
    const int i = static_cast<int>(side);
    const std::string what = std::string(to_string(side)) + " foot link";
    foot_frames[i] = find_frame(model, description.foot_links[i], what);
    std::vector<int> chain;
    int body = model.frames[foot_frames[i]].body;
    for (; body > 0 && body != base_body; body = model.parent[body])
      if (is_one_dof(model, body) && model.actuated[model.idx_v[body]])
        chain.push_back(body);
    if (body != base_body)
      throw std::invalid_argument(what + " = '" + description.foot_links[i] +
                                  "' is not below the base link '" + description.base_link + "'");
    if (chain.size() != 6) {
      std::ostringstream msg;
      msg << what << " = '" << description.foot_links[i] << "': the chain from the base link '"
          << description.base_link << "' has " << chain.size()
          << " actuated 1-DoF joints; a leg needs 6";
      throw std::invalid_argument(msg.str());
    }
    std::reverse(chain.begin(), chain.end());
    for (int k = 0; k < 6; ++k) {
      leg_joints[i][k] = chain[k];
      const auto it = std::find(joints.begin(), joints.end(), chain[k]);
      if (it == joints.end())
        throw std::invalid_argument("leg joint '" + model.joint_names[chain[k]] + "' of the " +
                                    to_string(side) + " leg is not a controlled joint");
      leg_columns[i][k] = static_cast<int>(it - joints.begin());
    }
    for (int j : leg_joints[i])
      if (i == 1 && std::find(leg_joints[0].begin(), leg_joints[0].end(), j) != leg_joints[0].end())
        throw std::invalid_argument("left foot link = '" + description.foot_links[1] +
                                    "': its leg shares joint '" + model.joint_names[j] +
                                    "' with the right leg");
    sole_frames[i] =
        find_frame(model,
                   description.sole_frames[i].empty() ? placed_sole_frame_name(description, side)
                                                      : description.sole_frames[i],
                   std::string(to_string(side)) + " sole frame");
    const int sole_body = model.frames[sole_frames[i]].body, ankle = leg_joints[i][5];
    if (sole_body < ankle || sole_body >= model.subtree_end[ankle])
      throw std::invalid_argument(std::string(to_string(side)) + " sole frame = '" +
                                  model.frames[sole_frames[i]].name +
                                  "': not below the last joint of the " + to_string(side) +
                                  " leg ('" + model.joint_names[ankle] + "')");
  }

  // Posture.
  posture = Eigen::VectorXd::Zero(n_joints());
  for (const auto& [name, value] : description.posture) {
    const auto it = std::find(joint_names.begin(), joint_names.end(), name);
    if (it == joint_names.end())
      throw std::invalid_argument("posture joint '" + name + "': " +
                                  (std::find(model.joint_names.begin(), model.joint_names.end(),
                                             name) == model.joint_names.end()
                                       ? "no such joint in the URDF"
                                       : "not a controlled joint"));
    posture[it - joint_names.begin()] = value;
  }
}

void Humanoid::to_configuration(const multibody::Model& model,
                                const Eigen::Ref<const Eigen::VectorXd>& angles,
                                Eigen::Ref<Eigen::VectorXd> q) const {
  for (int k = 0; k < n_joints(); ++k)
    q[model.idx_q[joints[k]]] = angles[k];
}

} // namespace plantar::walking
