#include "multibody/pd_gains.h"

#include <cmath>
#include <sstream>
#include <stdexcept>

namespace plantar::multibody {

PdGains PdGains::Zero(const Model& model) {
  return PdGains{Eigen::VectorXd::Zero(model.nv), Eigen::VectorXd::Zero(model.nv)};
}

PdGains PdGains::Uniform(const Model& model, double kp, double kd) {
  PdGains gains = Zero(model);
  for (int k = 0; k < model.nv; ++k) {
    if (model.actuated[k]) {
      gains.stiffness[k] = kp;
      gains.damping[k] = kd;
    }
  }
  gains.validate(model);
  return gains;
}

void PdGains::validate(const Model& model) const {
  if (stiffness.size() != model.nv || damping.size() != model.nv) {
    std::ostringstream msg;
    msg << "PdGains: stiffness has " << stiffness.size() << " and damping " << damping.size()
        << " entries, expected nv = " << model.nv;
    throw std::invalid_argument(msg.str());
  }
  for (int k = 0; k < model.nv; ++k) {
    if (!(stiffness[k] >= 0.0) || !(damping[k] >= 0.0) || !std::isfinite(stiffness[k]) ||
        !std::isfinite(damping[k])) {
      std::ostringstream msg;
      msg << "PdGains: dof " << k << " has stiffness " << stiffness[k] << " and damping "
          << damping[k] << ", allowed [0, inf)";
      throw std::invalid_argument(msg.str());
    }
    if (!model.actuated[k] && (stiffness[k] != 0.0 || damping[k] != 0.0)) {
      std::ostringstream msg;
      msg << "PdGains: dof " << k << " is not actuated (free base or passive joint) but has "
          << "stiffness " << stiffness[k] << " and damping " << damping[k] << ", allowed 0";
      throw std::invalid_argument(msg.str());
    }
  }
}

} // namespace plantar::multibody
