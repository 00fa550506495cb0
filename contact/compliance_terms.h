#pragma once
// The compliant sole in impulse form (paper eqs. 6, 7, 12).
//
// The contact-node velocity is the rigid velocity plus the deformation rate
// (eq. 6): v^t = W_F F^t + v_free + dU_c/dt. Backward difference (eq. 7) with
// the quasi-static sole U_c^t = C F^t (C = K_c^-1, eq. 11, m/N):
//   dU_c/dt = (C F^t - U_c^{t-dt}) / dt.
// Eq. 12 in forces: v^t = (W_F + C/dt) F^t + v_free - U_c^{t-dt}/dt.
// The solver's unknowns are impulses p = F^t dt (N s), and W_F = dt G G^T, so
//   v^t = (G G^T + C/dt^2) p + v_free - U_c^{t-dt}/dt,
//   U_c^t = C p / dt = dt (C/dt^2) p.
// CompliantPatch::compliance_over_dt holds C/dt^2; the deformation-rate term
// -U_c^{t-dt}/dt (all three components) is added to free_velocity.
// U_c^{t-dt} is the previous step's node displacement in the current contact
// frames (zero for a node that was not in contact: the sole is massless).
// These functions are the theta = 1 case. The multibody stepper's pads
// (coupling/pad_state.cc) use the Moreau-Jean theta method: their block is
// a C / (theta dt)^2 with a = theta / (beta / dt + theta) (a = 1 for an
// undamped pad, beta the Kelvin-Voigt damping time).

#include "contact/contact_problem.h"

namespace plantar::contact {

/// Sets patch.compliance_over_dt = C / dt^2 (allocates only if the size changes).
/// @param compliance C, (3 n x 3 n) with n = patch.n_contacts, m/N, patch frame
/// (patch.node_rotation(i) maps node i's rows to its contact frame).
/// @param dt time step, s, > 0. Throws std::invalid_argument on size or dt.
void set_patch_compliance(CompliantPatch& patch,
                          const Eigen::Ref<const Eigen::MatrixXd>& compliance, double dt);

/// free_velocity[patch rows] -= U_prev / dt (the deformation-rate term of eq. 12).
/// @param previous_displacement U_c^{t-dt}, (3 patch.n_contacts), m.
void add_deformation_rate_term(const CompliantPatch& patch,
                               const Eigen::Ref<const Eigen::VectorXd>& previous_displacement,
                               double dt, ContactProblem& problem);

/// U_c^t = dt A (C/dt^2) A^T p (A = blockdiag(a_i), CompliantPatch::node_rotation) for the patch's contacts: the node displacements (m)
/// after a solve, to pass as U_prev at the next step.
/// @param impulses all impulses of the problem (>= 3 n_contacts), N s.
/// @param displacement (3 patch.n_contacts), m. Does not allocate.
void patch_displacement(const CompliantPatch& patch,
                        const Eigen::Ref<const Eigen::VectorXd>& impulses, double dt,
                        Eigen::Ref<Eigen::VectorXd> displacement);

} // namespace plantar::contact
