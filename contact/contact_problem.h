#pragma once
// The velocity-level frictional contact problem of one time step
// (David et al. 2008, eqs. 4, 5 and 12; Moreau-Jean).
//
// For n active contacts, unknown impulses p (3n, N s), contact k owning rows
// 3k (normal), 3k+1, 3k+2 (two tangents), in its local frame:
//
//   v = W p + v_free                                 (3n, m/s)
//   W = W_gen + G G^T + blockdiag(C_j / dt^2)        (3n x 3n, m/(N s^2))
//
//   G (3n x m): the rigid part, J M^-1 J^T = G G^T with G = J L^-T, M = L L^T,
//               so W_rigid is applied through its low rank m (<= n_v).
//   C_j       : dense compliance of a compliant patch (a condensed sole,
//               m/N), A_j C_j,patch A_j^T with the block kept in the patch's
//               frame, A_j = blockdiag(a_i) (CompliantPatch::node_rotation). The paper's
//               eq. 12 is written for forces F: (W_F + C/dt) F with
//               W_F = dt J M^-1 J^T. With impulses p = F dt the same block is
//               C/dt^2 (theta = 1; the stepper's theta method fills a C/(theta dt)^2:
//               coupling/pad_state.cc, compliance_terms.h).
//   W_gen     : optional general matrix (general_delassus.h; empty for the robot), for
//               problems given as (W, q, mu), e.g. third-party ones.
//
// Conditions, per contact k (Signorini with Newton impact, exact Coulomb cone):
//   0 <= p_n  _|_  v_n + b_k >= 0,   ||p_t|| <= mu_k p_n,
//   and p_t opposes the sliding velocity when ||p_t|| = mu_k p_n.
//   b_k collects e v_n^- (restitution, eq. 5), the position correction and
//   the speculative gap term of the stepper (normal_bias() in
//   position_correction.h). The deformation-rate term of eq. 12,
//   -U_c^{t-dt}/dt, is three-dimensional and is added to free_velocity
//   (compliance_terms.h).
//
// Storage is sized once by resize(max_contacts, rigid_rank) before the time
// loop; each step sets n_contacts <= max_contacts and fills the leading rows,
// so building and solving a problem allocates nothing. (The patch matrices
// must likewise be sized before the loop.)

#include "contact/general_delassus.h"
#include "contact/hierarchical_compliance.h"
#include "contact/patch_lever.h"

#include <Eigen/Core>
#include <vector>

namespace plantar::contact {

/// A dense compliance block acting on the contiguous contacts
/// [first_contact, first_contact + n_contacts).
///
/// The block is held in the patch's own frame (e.g. the frame of the foot that
/// carries the sole), so that it stays constant while the body rotates:
///   W_patch = A compliance_over_dt A^T,  A = blockdiag(a_0, ..., a_{n-1}),
/// a_i (3x3, orthonormal) mapping patch-frame components to the contact frame of
/// contact i: a_i = rotation for every i (flat ground, one frame: A = I (x) R), or
/// the i-th 3 x 3 block of node_rotations when per_node_rotations (uneven ground,
/// contact/terrain.h: a_i = R_c,i^T R_body).
struct CompliantPatch {
  int first_contact = 0;
  int n_contacts = 0;
  /// (3 n_contacts x 3 n_contacts), symmetric positive semi-definite, the
  /// compliance block of the impulse-form Delassus operator, C / dt^2 in the
  /// patch frame, m/(N s^2). (The name follows eq. 12, where C/dt
  /// multiplies forces; set it with set_patch_compliance(), which divides the
  /// compliance C (m/N) by dt^2.)
  Eigen::MatrixXd compliance_over_dt;
  /// R: contact frame <- patch frame (orthonormal; identity: the block is
  /// already in the contact frames).
  Eigen::Matrix3d rotation = Eigen::Matrix3d::Identity();
  /// a_i of every contact (3 x 3 n_contacts, a_i in columns 3i..3i+2), used instead of
  /// rotation when per_node_rotations. Sized before the time loop (its owner keeps the size).
  Eigen::Matrix3Xd node_rotations;
  bool per_node_rotations = false;
  /// a_i of contact @p node of the patch (0 <= node < n_contacts).
  Eigen::Matrix3d node_rotation(int node) const {
    return per_node_rotations ? Eigen::Matrix3d(node_rotations.middleCols<3>(3 * node)) : rotation;
  }
  /// Optional: C (m/N, patch frame) compressed as an H-matrix (hierarchical_compliance.h), used
  /// instead of compliance_over_dt (then empty) as the block compressed_scale C, with
  /// compressed_scale = 1/dt^2 (or 1/(theta dt)^2). Not owned; compressed->n_nodes() must equal
  /// n_contacts. Only the Gauss-Seidel solver takes it (ContactSolver refuses the others and the
  /// direct solve on the sticking set); warm_product is not used.
  const HierarchicalCompliance* compressed = nullptr;
  double compressed_scale = 1.0;
  /// C_kk of node @p node (3 x 3, patch frame, m/(N s^2)) from the dense or compressed block.
  Eigen::Matrix3d node_block(int node) const {
    return compressed != nullptr
               ? Eigen::Matrix3d(compressed_scale * compressed->diagonal_block(node))
               : Eigen::Matrix3d(compliance_over_dt.block<3, 3>(3 * node, 3 * node));
  }
  /// Optional warm-start product (3 n_contacts, m/s, patch frame):
  /// compliance_over_dt (I (x) R)^T p0 for the impulses p0 the solver starts
  /// from. Used by the Gauss-Seidel solver instead of the product (one pass
  /// over the block) when warm_product_valid; the caller keeps it from
  /// ContactSolver::patch_product() of the previous solve.
  Eigen::VectorXd warm_product;
  bool warm_product_valid = false;
};

/// x (3 n) <- (I (x) R^T) x: contact-frame vectors of a patch to its frame.
void rotate_to_patch(const Eigen::Matrix3d& rotation, Eigen::Ref<Eigen::VectorXd> x);
/// x (3 n) <- (I (x) R) x: patch-frame vectors to the contact frames.
void rotate_from_patch(const Eigen::Matrix3d& rotation, Eigen::Ref<Eigen::VectorXd> x);
/// x (3 n, n <= patch.n_contacts, node-major from the patch's first contact) <- A^T x with
/// A = blockdiag(a_i) of @p patch: contact frames to the patch frame.
void rotate_to_patch(const CompliantPatch& patch, Eigen::Ref<Eigen::VectorXd> x);
/// x <- A x: the patch frame to the contact frames.
void rotate_from_patch(const CompliantPatch& patch, Eigen::Ref<Eigen::VectorXd> x);

struct ContactProblem {
  /// Allocates storage for up to @p max_contacts contacts and a rigid factor
  /// with @p rigid_rank columns. Call once, outside the time loop.
  void resize(int max_contacts, int rigid_rank) {
    rigid_factor.setZero(3 * max_contacts, rigid_rank);
    free_velocity.setZero(3 * max_contacts);
    normal_bias.setZero(max_contacts);
    friction.setZero(max_contacts);
    n_contacts = 0;
  }
  int max_contacts() const { return static_cast<int>(friction.size()); }
  /// Number of columns m of the rigid factor G.
  int rigid_rank() const { return static_cast<int>(rigid_factor.cols()); }

  /// Throws std::invalid_argument naming the field and value if sizes,
  /// friction (mu >= 0, finite), patch ranges (disjoint, inside
  /// [0, n_contacts), square blocks of size 3 n_contacts) or data are invalid.
  /// @param check_matrices also check that G and the patch blocks are finite (one
  /// pass over W; ContactSolver::solve skips it and reports non-finite data as
  /// SolverStatus::non_finite instead). Does not allocate.
  void validate(bool check_matrices = true) const;

  /// W_kk (3x3): diagonal block of contact k, G_k G_k^T + a_k C_kk a_k^T.
  Eigen::Matrix3d diagonal_block(int contact) const;
  /// trace(W_kk) = ||G_k||_F^2 + trace(C_j,kk/dt^2) of every contact (the rotation drops
  /// out), (m/s)/(N s), into @p traces (size >= n_contacts). One pass over G. Does not allocate.
  void diagonal_traces(Eigen::Ref<Eigen::VectorXd> traces) const;

  /// out = W p for the leading 3 n_contacts rows, applying G G^T through its
  /// low rank: out = G (G^T p) + blockdiag(A_j C_j/dt^2 A_j^T) p.
  /// @param p (3 n_contacts) impulses, N s.
  /// @param rigid_work (>= max(m, 3 n_contacts)) scratch.
  /// @param out (3 n_contacts) velocities, m/s. Does not allocate.
  void apply_delassus(const Eigen::Ref<const Eigen::VectorXd>& p,
                      Eigen::Ref<Eigen::VectorXd> rigid_work,
                      Eigen::Ref<Eigen::VectorXd> out) const;

  /// Dense W (3 n_contacts square), for tests, diagnostics and small problems
  /// (allocates when @p delassus is resized).
  void assemble_delassus(Eigen::MatrixXd& delassus) const;
  /// Writes W (or its symmetric part (W + W^T)/2 when @p symmetric_part) into the leading
  /// 3 n_contacts square of @p delassus (at least that large). Does not allocate.
  void assemble_delassus_into(Eigen::Ref<Eigen::MatrixXd> delassus,
                              bool symmetric_part = false) const;

  int n_contacts = 0;                  ///< active contacts, first rows used
  Eigen::MatrixXd rigid_factor;        ///< G, (3 max_contacts x m)
  std::vector<CompliantPatch> patches; ///< compliant blocks, disjoint ranges
  /// W_gen: empty, or of size 3 n_contacts (set after n_contacts, see general_delassus.h).
  GeneralDelassus general;
  /// Optional rigid structure of each patch (empty, or parallel to patches), for the direct
  /// solve on the warm start's active set (SolverSettings::sticking_direct).
  std::vector<PatchLever> patch_levers;
  Eigen::VectorXd free_velocity; ///< v_free, (3 max_contacts), m/s
  Eigen::VectorXd normal_bias;   ///< b, (max_contacts), m/s
  Eigen::VectorXd friction;      ///< mu, (max_contacts), dimensionless
};

} // namespace plantar::contact
