#include "contact/patch_lever.h"

#include <atomic>
#include <stdexcept>
#include <string>

namespace plantar::contact {

Eigen::MatrixXd rigid_lever(const Eigen::Matrix3Xd& nodes) {
  Eigen::MatrixXd lever = Eigen::MatrixXd::Zero(3 * nodes.cols(), 6);
  for (Eigen::Index k = 0; k < nodes.cols(); ++k) {
    const Eigen::Vector3d r = nodes.col(k);
    lever.block<3, 3>(3 * k, 0).setIdentity();
    lever.block<3, 3>(3 * k, 3) << 0, r.z(), -r.y(), -r.z(), 0, r.x(), r.y(), -r.x(), 0;
  }
  return lever;
}

void set_sticking_structure(PatchLever& patch_lever,
                            const Eigen::Ref<const Eigen::MatrixXd>& lever) {
  if (lever.cols() != 6 || lever.rows() % 3 != 0)
    throw std::invalid_argument("ContactProblem: set_sticking_structure: lever is " +
                                std::to_string(lever.rows()) + "x" + std::to_string(lever.cols()) +
                                ", expected 3n x 6");
  static std::atomic<long> next_version{1};
  if (lever.data() != patch_lever.lever.data())
    patch_lever.lever = lever;
  patch_lever.version = next_version++;
}

} // namespace plantar::contact
