#include "contact/compliance_terms.h"

#include <cmath>
#include <sstream>
#include <stdexcept>

namespace plantar::contact {

namespace {
void check_dt(double dt, const char* where) {
  if (!(dt > 0.0) || !std::isfinite(dt)) {
    std::ostringstream msg;
    msg << where << ": dt = " << dt << " s, allowed (0, inf)";
    throw std::invalid_argument(msg.str());
  }
}
} // namespace

void set_patch_compliance(CompliantPatch& patch,
                          const Eigen::Ref<const Eigen::MatrixXd>& compliance, double dt) {
  check_dt(dt, "set_patch_compliance");
  const int size = 3 * patch.n_contacts;
  if (compliance.rows() != size || compliance.cols() != size) {
    std::ostringstream msg;
    msg << "set_patch_compliance: compliance is " << compliance.rows() << "x" << compliance.cols()
        << ", expected " << size << "x" << size << " (3 x patch.n_contacts)";
    throw std::invalid_argument(msg.str());
  }
  patch.compliance_over_dt.resize(size, size);
  patch.compliance_over_dt = compliance / (dt * dt);
}

void add_deformation_rate_term(const CompliantPatch& patch,
                               const Eigen::Ref<const Eigen::VectorXd>& previous_displacement,
                               double dt, ContactProblem& problem) {
  check_dt(dt, "add_deformation_rate_term");
  const int size = 3 * patch.n_contacts;
  if (previous_displacement.size() != size) {
    std::ostringstream msg;
    msg << "add_deformation_rate_term: previous_displacement has " << previous_displacement.size()
        << " entries, expected " << size;
    throw std::invalid_argument(msg.str());
  }
  problem.free_velocity.segment(3 * patch.first_contact, size) -= previous_displacement / dt;
}

void patch_displacement(const CompliantPatch& patch,
                        const Eigen::Ref<const Eigen::VectorXd>& impulses, double dt,
                        Eigen::Ref<Eigen::VectorXd> displacement) {
  check_dt(dt, "patch_displacement");
  const int size = 3 * patch.n_contacts;
  auto u = displacement.head(size);
  u.setZero();
  for (int j = 0; j < size; j += 3) {
    const Eigen::Vector3d p_patch =
        patch.node_rotation(j / 3).transpose() * impulses.segment<3>(3 * patch.first_contact + j);
    u.noalias() += patch.compliance_over_dt.middleCols<3>(j) * p_patch;
  }
  rotate_from_patch(patch, u);
  u *= dt;
}

} // namespace plantar::contact
