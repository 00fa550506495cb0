#pragma once
// Condensation of a linear-elastic FEM sole onto its contact nodes
// (David et al. 2008, eq. 11; Duriez et al. 2006).
//
// The free dofs of K u = f (the attached "top" nodes are Dirichlet, u = 0,
// and are removed) are split into the contact dofs c (the 3 n_c dofs of the
// n_c nodes of the contact surface, node-major) and the remaining dofs n:
//
//          c      n
//       +------+------+   +-----+   +-----+
//     c | K_cc | K_cn |   | u_c |   | f_c |
//       +------+------+ * +-----+ = +-----+      (no load on the n dofs)
//     n | K_nc | K_nn |   | u_n |   |  0  |
//       +------+------+   +-----+   +-----+
//
//   u_n = -K_nn^-1 K_nc u_c                      (recovery of the interior)
//   K_c = K_cc - K_cn K_nn^-1 K_nc               (Schur complement, eq. 11)
//   C   = K_c^-1 = [K^-1]_cc                     (contact compliance, m/N)
//
// C is computed as the contact block of K^-1: one sparse Cholesky
// factorization of K (CHOLMOD, supernodal), then K x = e_j for the 3 n_c
// contact dofs (blocks of right-hand sides), keeping the contact rows of x.
// That factorization is released afterwards; the recovery keeps a
// factorization of K_nn and applies u_n = -K_nn^-1 (K_nc u_c) on demand.
//
// With CondensationParameters::form = factorization, C is never formed: the
// factorization of K is kept instead, and products with C come from solves,
//
//   A^T C A = (B A)^T K^-1 (B A)     (m solves for A of m columns),
//   u = K^-1 B f_c                   (the field of contact forces f_c),
//
// with B (n_free x 3 n_c) the injection of the contact dofs: a reduced sole
// (reduced_sole.h) of P patches costs 3 P solves instead of 3 n_c, and keeps
// no dense 3 n_c x 3 n_c matrix. The rigid-motion stiffness of the contact
// face, K_R = R^T K_c R (6 x 6, rigid_motion_stiffness()), is computed in both
// forms without C: K_c R = [K x]_c with x_c = R, x_n = -K_nn^-1 K_nc R.
//
// A CondensedSole is constant after construction (like a Pinocchio Model):
// contact node positions, C, optionally K_c, and the recovery operator. The
// stepper takes contact_positions() and compliance() (sole frame); see
// contact_frame_compliance.h for the contact-frame form.

#include "fem/linear_elasticity.h"
#include "fem/material_table.h"

#include <deal.II/grid/tria.h>
#include <deal.II/lac/vector.h>

#include <Eigen/Core>
#include <Eigen/SparseCore>

#include <array>
#include <cstddef>
#include <filesystem>
#include <memory>
#include <vector>

namespace plantar::coupling {

struct CondensationParameters {
  /// What the condensation keeps (see above).
  enum class Form {
    dense,        ///< C (3 n_c solves, 8 (3 n_c)^2 bytes) and the factor of K_nn
    factorization ///< the factor of K, no C (compliance() is empty, recover() throws)
  };
  Form form = Form::dense;
  /// Boundary id of the attached face (the sole's "top"): u = 0 there.
  dealii::types::boundary_id attached_boundary = 0;
  /// Boundary id of the contact face (the sole's "bottom"): its nodes are the contact nodes.
  dealii::types::boundary_id contact_boundary = 1;
  unsigned int degree = 1;        ///< Lagrange degree, 1 or 2 (P1/P2 or Q1/Q2 by the mesh)
  int block_size = 64;            ///< right-hand sides per block solve, [1, 4096]
  bool compute_stiffness = false; ///< also store K_c = C^-1 (dense, inverse of C)
  /// Throws std::invalid_argument naming the field, its value and the range.
  void validate() const;
};

/// Wall-clock seconds of each precomputation stage.
struct CondensationTimings {
  double assembly = 0;               ///< dofs, sparsity and K assembly (deal.II)
  double factorization = 0;          ///< Cholesky of K (free dofs)
  double contact_solves = 0;         ///< the 3 n_c solves K x = e_j
  double recovery_factorization = 0; ///< Cholesky of K_nn
  double stiffness = 0;              ///< K_c = C^-1 (only if requested)
  double total() const {
    return assembly + factorization + contact_solves + recovery_factorization + stiffness;
  }
};

/// Bytes held by a CondensedSole, and the peak factorization of K during the
/// precomputation (released after it).
struct CondensationMemory {
  std::size_t compliance_bytes = 0;                 ///< dense C, 8 (3 n_c)^2
  std::size_t stiffness_bytes = 0;                  ///< dense K_c if stored
  std::size_t recovery_factorization_bytes = 0;     ///< CHOLMOD factor of K_nn (+ workspace)
  std::size_t sparse_matrix_bytes = 0;              ///< K_nn and K_nc (CSC) + deal.II K
  std::size_t condensation_factorization_bytes = 0; ///< factor of K (kept by Form::factorization)
  /// Bytes kept after construction (and after release_factorization()).
  std::size_t total() const {
    return compliance_bytes + stiffness_bytes + recovery_factorization_bytes + sparse_matrix_bytes;
  }
};

class CondensedSole {
public:
  /// Builds the sole on a copy of @p triangulation with the materials
  /// @p materials (copied), assembles K, and condenses it (see above).
  /// @throws std::invalid_argument if parameters are out of range, a boundary
  ///   id has no face, or a contact node has a constrained component;
  /// @throws std::runtime_error if K (free dofs) is not positive definite (e.g.
  ///   nothing attached) or C is not finite.
  CondensedSole(const dealii::Triangulation<3>& triangulation, const fem::MaterialTable& materials,
                const CondensationParameters& parameters);
  ~CondensedSole();
  CondensedSole(CondensedSole&&) noexcept;
  CondensedSole& operator=(CondensedSole&&) noexcept;

  int n_contacts() const { return static_cast<int>(contact_positions_.rows()); }
  /// Number of dofs of the full FEM field (including the attached ones).
  int n_dofs() const;
  /// Contact node positions in the mesh (sole) frame, (n_c x 3), m; row k is node k.
  const Eigen::MatrixX3d& contact_positions() const { return contact_positions_; }
  /// C = K_c^-1, (3 n_c x 3 n_c), m/N, sole frame, node-major (rows 3k..3k+2 =
  /// x, y, z of node k); symmetric (symmetrized: see raw_asymmetry()) and SPD.
  /// Empty with Form::factorization.
  const Eigen::MatrixXd& compliance() const { return compliance_; }
  /// A^T C A (m x m, m/N) for @p aggregation A (3 n_c x m, dimensionless, node-major rows):
  /// from C (Form::dense) or by m solves with the kept factor of K, in blocks of
  /// parameters().block_size columns (Form::factorization); symmetrized. Allocates.
  /// Throws std::invalid_argument on A's row count.
  Eigen::MatrixXd
  projected_compliance(const Eigen::SparseMatrix<double, Eigen::ColMajor, int>& aggregation) const;
  /// The full displacement field (n_dofs, deal.II dof order, m) of the contact forces
  /// @p contact_force f_c (3 n_c, N, sole frame, node-major): u = K^-1 B f_c, 0 on attached
  /// dofs; its contact rows are C f_c. One solve (Form::factorization) or C f_c then recover()
  /// (Form::dense). Allocates. Throws std::invalid_argument on size.
  void displacement_of_forces(const Eigen::Ref<const Eigen::VectorXd>& contact_force,
                              dealii::Vector<double>& displacement) const;
  /// Form::factorization: frees the factor of K (no more projected_compliance or fields:
  /// they throw std::logic_error), e.g. once a reduced sole is built and no field is written.
  void release_factorization();
  /// Whether the solves above are available (Form::dense, or a factor not released).
  bool has_solver() const;
  /// Stiffness of the contact face against rigid motions about the contact nodes' centroid
  /// (6 x 6; N/m, N/rad, N m/rad): K_R = R^T C^-1 R with R_k = [I_3, -[x_k - x_0]_x],
  /// x_0 = mean of contact_positions(); computed at construction through K_nn (both forms).
  const Eigen::Matrix<double, 6, 6>& rigid_motion_stiffness() const { return rigid_stiffness_; }
  /// K_c R (3 n_c x 6; N per m, N per rad): the contact forces holding the contact face in each
  /// rigid motion of rigid_motion_stiffness() (coupling::rigid_motion_forces without C);
  /// computed at construction (both forms).
  const Eigen::MatrixXd& rigid_motion_forces() const { return rigid_forces_; }
  /// K_c, (3 n_c x 3 n_c), N/m; empty unless parameters.compute_stiffness.
  const Eigen::MatrixXd& stiffness() const { return stiffness_; }
  /// max |C - C^T| / max |C| of the computed C before symmetrization.
  double raw_asymmetry() const { return raw_asymmetry_; }
  /// Global dof indices (x, y, z) of contact node k.
  const std::vector<std::array<dealii::types::global_dof_index, 3>>& contact_dofs() const {
    return contact_dofs_;
  }

  /// Full displacement field (n_dofs, deal.II dof order, m) from the contact
  /// displacements: u_c on the contact dofs, u_n = -K_nn^-1 K_nc u_c on the
  /// others (one solve with the stored factorization), 0 on attached dofs.
  /// @param contact_displacement u_c, (3 n_c), m, sole frame, node-major.
  /// Allocates (output, not per time step). Throws std::invalid_argument on size,
  /// std::logic_error with Form::factorization (no factor of K_nn kept).
  void recover(const Eigen::Ref<const Eigen::VectorXd>& contact_displacement,
               dealii::Vector<double>& displacement) const;

  /// Consistent nodal forces f_i = int_Gamma_c N_i t ds (N) of the uniform
  /// traction @p traction (Pa, sole frame) on the contact face, (3 n_c),
  /// node-major. Their sum is t times the contact area.
  void contact_load(const Eigen::Vector3d& traction, Eigen::Ref<Eigen::VectorXd> forces) const;

  /// Writes the recovered field of @p contact_displacement with its strain
  /// and stress to @p path (.vtu, fem/field_output.h). Not thread-safe. Form::dense only.
  void write_vtu(const Eigen::Ref<const Eigen::VectorXd>& contact_displacement,
                 const std::filesystem::path& path) const;

  /// The FEM problem (dof handler, K with Dirichlet rows eliminated).
  const fem::LinearElasticity& elasticity() const;
  const CondensationParameters& parameters() const { return parameters_; }
  const CondensationTimings& timings() const { return timings_; }
  const CondensationMemory& memory() const { return memory_; }

private:
  struct Impl; // deal.II objects and the CHOLMOD factor of K_nn
  std::unique_ptr<Impl> impl_;
  CondensationParameters parameters_;
  std::vector<std::array<dealii::types::global_dof_index, 3>> contact_dofs_;
  Eigen::MatrixX3d contact_positions_;
  Eigen::MatrixXd compliance_, stiffness_;
  Eigen::Matrix<double, 6, 6> rigid_stiffness_ = Eigen::Matrix<double, 6, 6>::Zero();
  Eigen::MatrixXd rigid_forces_;
  double raw_asymmetry_ = 0;
  CondensationTimings timings_;
  CondensationMemory memory_;
};

} // namespace plantar::coupling
