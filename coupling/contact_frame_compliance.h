#pragma once
// A condensed sole's compliance C (sole frame, coupling/condensed_sole.h)
// expressed in per-contact frames, the form the contact problem uses
// (contact/contact_problem.h: rows n, t1, t2 of each contact).
//
// The sole frame is rotated into the world by R (foot orientation), and
// contact k has the world frame F_k = [n_k t1_k t2_k] (orthonormal columns).
// A displacement u_k (sole frame) reads A_k u_k in contact k's frame with
//   A_k = F_k^T R   (3 x 3, contact frame <- sole frame),
// and a contact-frame force f_k acts on the sole as A_k^T f_k, so blockwise
//   C_contact(k, l) = A_k C(k, l) A_l^T   (= F_k^T (R C(k, l) R^T) F_l),
// i.e. C_world = R C R^T blockwise, then projected onto the contact frames.
// The stepper (multibody/stepper.cc) divides the result by (theta dt)^2 for the sole block
// of contact::CompliantPatch (compliance_terms.h); theta = 1 (the default) gives C / dt^2.

#include <Eigen/Core>

namespace plantar::coupling {

/// Writes C_contact(k, l) = A_k C(k, l) A_l^T with A_k = F_k^T R (see above).
/// @param compliance C, (3 n x 3 n), m/N, sole frame, node-major blocks
///        (rows 3k..3k+2 = x, y, z of node k).
/// @param rotation R (3 x 3), sole frame -> world, orthonormal.
/// @param frames (3 x 3 n), world; columns 3k, 3k+1, 3k+2 = n_k, t1_k, t2_k.
/// @param out (3 n x 3 n), m/N, contact frames (rows 3k = normal, 3k+1, 3k+2
///        = tangents); must not alias @p compliance.
/// Does not allocate. Throws std::invalid_argument naming the argument, its
/// size and the expected size, or the contact whose frame (or R) is not
/// orthonormal to 1e-9.
void rotate_compliance_to_contact_frames(const Eigen::Ref<const Eigen::MatrixXd>& compliance,
                                         const Eigen::Matrix3d& rotation,
                                         const Eigen::Ref<const Eigen::MatrixXd>& frames,
                                         Eigen::Ref<Eigen::MatrixXd> out);

/// Writes C_rotated(k, l) = R C(k, l) R^T for every 3 x 3 block (k, l): the
/// compliance in the frame that R maps the sole frame into (e.g. the foot
/// body's frame). The identity-frames case of
/// rotate_compliance_to_contact_frames (F_k = I), with the same arithmetic:
/// results are bitwise the same.
/// @param rotation R (3 x 3), orthonormal (to 1e-9).
/// @param compliance C, (3 n x 3 n), m/N, node-major blocks.
/// @param out (3 n x 3 n), m/N; must not alias @p compliance.
/// Does not allocate. Throws std::invalid_argument naming the argument and its
/// size, or if R is not orthonormal.
void rotate_compliance(const Eigen::Matrix3d& rotation,
                       const Eigen::Ref<const Eigen::MatrixXd>& compliance,
                       Eigen::Ref<Eigen::MatrixXd> out);

} // namespace plantar::coupling
