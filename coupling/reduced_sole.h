#pragma once
// A reduced sole: the condensed compliance of a sole (condensed_sole.h) aggregated onto
// coarser contact patches, one contact point per patch.
//
// A patch force F_j (N) is shared by the nodes (of n, positions x_k) with the shares S_kj >= 0,
// sum_k S_kj = 1 (the share matrix S, n x P), f_k = sum_j S_kj F_j, and the patch displacement
// is the weighted mean U_j = sum_k S_kj u_k. With the aggregation matrix A = S (x) I_3
// (3n x 3P):
//
//   f = A F,   U = A^T u,   C_r = A^T C A   (3P x 3P, m/N),   X_j = sum_k S_kj x_k
//
// Two bases (PatchBasis) on a grid of cells:
// - constant: a patch is a cell; node k (weight w_k > 0) of cell j has S_kj = w_k / W_j,
//   W_j = sum_{k in j} w_k: a patch-wise constant pressure when the weights are the nodes'
//   areas.
// - bilinear: a patch is a grid vertex v with its hat function phi_v (bilinear on each cell,
//   1 at v, 0 at the other vertices); S_kv = phi_v(x_k) w_k / sum_i phi_v(x_i) w_i. The patch
//   forces are then the consistent nodal forces of a continuous, cell-wise bilinear pressure
//   (pressure F_v / W_v at vertex v with area weights), nonnegative wherever every F_v,n is:
//   the Signorini condition of a patch is that of a pressure interpolated from the vertices.
//
// Equal weights share a patch force equally among its nodes (s_k = 1 / n_j). The nodes'
// consistent areas a_k = int N_k ds as weights (pressure_weights) make the patch's pressure
// uniform, f_k = (F_j / A_j) a_k: the consistent nodal forces of a patch-wise constant
// traction, the natural choice on any mesh and the only sensible one for P2 faces, whose
// vertex nodes carry no area.
//
// C_r is symmetric positive definite when C is. Restricting the forces to patch-wise constant
// ones is a Galerkin (complementary energy) reduction: for any rigid motion a of the contact
// face, the reduced stiffness a^T R_r^T C_r^-1 R_r a never exceeds the full one
// a^T R^T C^-1 R a and grows monotonically under nested refinement; with one node per patch
// C_r = C. (R maps a rigid motion to node displacements, R_r the same at the patch centres.)
//
// Patches from a grid: the nodes' bounding box in the sole's x-y plane split into nx x ny
// cells, equal (GridSpacing::uniform) or graded towards the edges, where the contact pressure
// of a bonded layer peaks (GridSpacing::chebyshev: cell edges at the Chebyshev-Lobatto points
// lo + (hi - lo)(1 - cos(pi i / m)) / 2, i = 0..m); empty cells (constant) or vertices whose
// hat covers no node (bilinear) are dropped. Grids whose nx, ny double are nested in either
// spacing and basis.
// Built from the dense C, or from a CondensedSole's factorization of K (Form::factorization):
// C_r = (B A)^T K^-1 (B A) by 3P solves, without C (condensed_sole.h). Constant after
// construction.

#include <Eigen/Core>
#include <Eigen/SparseCore>

#include <vector>

namespace plantar::coupling {

class CondensedSole;

/// How grid_patches() spaces its cells (see above).
enum class GridSpacing { uniform, chebyshev };
/// The pressure of a patch force over the grid (see above): one patch per cell, or per vertex.
enum class PatchBasis { constant, bilinear };

class ReducedSole {
public:
  using ShareMatrix = Eigen::SparseMatrix<double, Eigen::ColMajor, int>;

  /// @p positions (n x 3, m, sole frame) and @p compliance (3n x 3n, m/N, node-major) of the
  /// full condensed sole; @p shares (n x P) the share matrix S: nonnegative, every column
  /// summing to 1. Throws std::invalid_argument naming the argument on bad sizes, a negative
  /// share or a column that does not sum to 1.
  ReducedSole(const Eigen::MatrixX3d& positions, const Eigen::MatrixXd& compliance,
              const ShareMatrix& shares);
  /// The same from @p sole's projected_compliance (3P solves with Form::factorization).
  ReducedSole(const CondensedSole& sole, const ShareMatrix& shares);

  /// @p positions (n x 3, m, sole frame) and @p compliance (3n x 3n, m/N, node-major) of the
  /// full condensed sole; @p patch_of_node (n) the patch of each node, values in [0, P) with
  /// every patch non-empty. Throws std::invalid_argument naming the argument on bad sizes or
  /// an empty patch.
  /// @p weights (n, > 0; empty: equal) the nodes' weights w_k.
  ReducedSole(const Eigen::MatrixX3d& positions, const Eigen::MatrixXd& compliance,
              const std::vector<int>& patch_of_node, const Eigen::VectorXd& weights = {});
  /// The same from @p sole's projected_compliance (either form; 3P solves with
  /// Form::factorization). Same throws.
  ReducedSole(const CondensedSole& sole, const std::vector<int>& patch_of_node,
              const Eigen::VectorXd& weights = {});

  /// A (3n x 3P, sparse, dimensionless): A_kj = s_k I_3 for node k in patch j (shares of
  /// @p weights, equal when empty), P the largest value of @p patch_of_node plus one. Throws
  /// std::invalid_argument on an empty patch, a negative patch or a weight that is not > 0.
  static ShareMatrix aggregation(const std::vector<int>& patch_of_node,
                                 const Eigen::VectorXd& weights = {});
  /// A = S (x) I_3 (3n x 3P) of a share matrix @p shares (n x P).
  static ShareMatrix aggregation(const ShareMatrix& shares);
  /// The share matrix (n x P) of a partition: S_kj = w_k / W_j for node k in patch j. Same
  /// arguments and throws as aggregation().
  static ShareMatrix partition_shares(const std::vector<int>& patch_of_node,
                                      const Eigen::VectorXd& weights = {});
  /// The share matrix (n x P) of an @p nx x @p ny grid over the nodes' x-y bounding box in
  /// @p basis (constant: the cells of grid_patches; bilinear: the (nx + 1)(ny + 1) vertices'
  /// hats, those covering no node dropped), node weights @p weights (n, > 0; empty: equal).
  /// Throws std::invalid_argument as grid_patches and on a bad weight.
  static ShareMatrix grid_shares(const Eigen::MatrixX3d& positions, int nx, int ny,
                                 GridSpacing spacing, PatchBasis basis,
                                 const Eigen::VectorXd& weights = {});

  /// Patches from an @p nx x @p ny grid over the nodes' x-y bounding box (nx, ny >= 1), its
  /// cells spaced by @p spacing.
  static std::vector<int> grid_patches(const Eigen::MatrixX3d& positions, int nx, int ny,
                                       GridSpacing spacing = GridSpacing::uniform);

  int n_patches() const { return static_cast<int>(shares_.cols()); }
  int n_nodes() const { return static_cast<int>(shares_.rows()); }
  /// Patch centres X_j = sum_k S_kj x_k (P x 3, m, sole frame).
  const Eigen::MatrixX3d& patch_positions() const { return patch_positions_; }
  /// C_r = A^T C A (3P x 3P, m/N, sole frame, patch-major), symmetrized.
  const Eigen::MatrixXd& compliance() const { return compliance_; }
  /// Nodes with a nonzero share in each patch.
  const std::vector<int>& patch_sizes() const { return patch_sizes_; }
  /// The share matrix S (n x P; each column sums to 1).
  const ShareMatrix& shares() const { return shares_; }

private:
  /// Patch sizes and centres; checks the sizes and the shares.
  void set_patches(const Eigen::MatrixX3d& positions, int n_compliance_rows);

  ShareMatrix shares_;
  std::vector<int> patch_sizes_;
  Eigen::MatrixX3d patch_positions_;
  Eigen::MatrixXd compliance_;
};

/// R (3n x 6, m per m and m per rad): the displacements of points @p positions (n x 3, m)
/// under the rigid motions about @p origin, R_k = [I_3, -[x_k - x_0]_x] (translation, then
/// rotation about x, y, z).
Eigen::MatrixXd rigid_motion_map(const Eigen::MatrixX3d& positions, const Eigen::Vector3d& origin);

/// F = C^-1 R (3n x 6; N per m, N per rad): the contact forces that hold the contact face of
/// the sole of @p compliance (3n x 3n, m/N) at @p positions (n x 3, m) in each rigid motion of
/// rigid_motion_map about @p origin (m): the bonded face's response. Dense route (one LDLT of
/// C); CondensedSole::rigid_motion_forces gives the same through K_nn. Allocates.
Eigen::MatrixXd rigid_motion_forces(const Eigen::MatrixX3d& positions,
                                    const Eigen::MatrixXd& compliance,
                                    const Eigen::Vector3d& origin);

/// Stiffness of the contact face against rigid motions (6 x 6): K = R^T C^-1 R with
/// R = rigid_motion_map (translation then rotation, rad), @p positions
/// (n x 3, m), @p compliance (3n x 3n, m/N), @p origin x_0 (m). Units: N/m, N/rad, N m/rad.
/// Used to compare a reduced sole with the full one. Allocates.
Eigen::Matrix<double, 6, 6> rigid_motion_stiffness(const Eigen::MatrixX3d& positions,
                                                   const Eigen::MatrixXd& compliance,
                                                   const Eigen::Vector3d& origin);

/// The reduction error estimate of a reduced sole: the scaled error of its contact face's
/// rigid-motion stiffness,
///
///   e = || D^-1/2 (K - K_r) D^-1/2 ||_2,   D = diag(K),
///
/// K the full sole's rigid_motion_stiffness about @p origin (@p k_full), K_r the reduced
/// sole's at its patch centres (with fewer than 3 patches, by R_r^T C_r^-1 R_r, which is
/// singular in the rotations: e >= 1). 0 <= e; e = 0 with one node per patch; e falls
/// monotonically under nested refinement (K_r <= K in the Loewner order, reduced_sole test).
/// e bounds the relative error of the face's stiffness in every rigid direction. Allocates.
double reduction_error_estimate(const Eigen::Matrix<double, 6, 6>& k_full,
                                const ReducedSole& reduced, const Eigen::Vector3d& origin);

/// The pressure error estimate of a reduced sole: the worst relative error of the contact
/// face's normal nodal forces (sole frame z) over the rigid motions that press the bonded face,
/// a in span(z translation, rotations about x and y through @p origin):
///
///   e_p = max_a || N (A C_r^-1 R_r - F) a ||_2 / || N F a ||_2 = sqrt(lambda_max(H, G)),
///
/// F = C^-1 R the full sole's rigid_motion_forces about the same @p origin (@p forces_full,
/// 3n x 6; CondensedSole's are about the nodes' centroid), A the reduced sole's
/// aggregation, R_r = A^T R the rigid motions at its patch centres, N the rows of the normal
/// components; G = (N F)^T (N F) and H the same of the difference, restricted to the three
/// motions (a 3 x 3 generalized eigenproblem). It is the relative L2 error of the nodal normal
/// force field (work_precision's e_field) of a sole fully in sticking contact with a flat
/// ground, the foot in any pitch, roll and approach. 0 with one node per patch; not monotone
/// under refinement in general. Allocates.
double pressure_error_estimate(const Eigen::MatrixXd& forces_full, const ReducedSole& reduced,
                               const Eigen::Vector3d& origin);

/// What choose_reduction's tolerance bounds (Sole/Reduction quantity).
enum class ReductionQuantity {
  stiffness, ///< reduction_error_estimate: the face's rigid-motion stiffness, hence its
             ///< approach and tilt under a given wrench
  pressure   ///< pressure_error_estimate: the normal nodal force field of the bonded face
};

/// The grid chosen by choose_reduction().
struct ReductionChoice {
  int grid = 0;                 ///< g of the g x g grid; 0: the full sole
  int n_patches = 0;            ///< contacts of the chosen sole (the nodes for the full sole)
  double estimate = 0;          ///< reduction_error_estimate of the choice (0 for the full sole)
  double pressure_estimate = 0; ///< pressure_error_estimate of the choice (0 for the full sole)
  bool reached = true; ///< false: no reduced grid met the tolerance, the full sole is chosen
  /// The estimate of @p quantity.
  double estimate_of(ReductionQuantity quantity) const {
    return quantity == ReductionQuantity::pressure ? pressure_estimate : estimate;
  }
};

/// The cheapest sole whose estimate of @p quantity (reduction_error_estimate or
/// pressure_error_estimate) is at most @p tolerance (> 0): the
/// coarsest g x g grid over the nodes' bounding box (grid_shares in @p spacing and @p basis,
/// node weights @p weights) with fewer patches than nodes; otherwise the full sole (reached =
/// false). The nested grids g = 1, 2, 4, ... bracket g (the last that misses the tolerance, the
/// first that meets it), then bisection: the coarsest g when the estimate falls with g, and in
/// any case a grid whose estimate meets the tolerance. @p positions (n x 3, m) and @p compliance
/// (3n x 3n, m/N) of the full condensed sole; the origin is the nodes' centroid. Cost: one dense
/// factorisation of C and one of each candidate's C_r. Throws std::invalid_argument on tolerance <=
/// 0.
ReductionChoice choose_reduction(const Eigen::MatrixX3d& positions,
                                 const Eigen::MatrixXd& compliance, double tolerance,
                                 GridSpacing spacing = GridSpacing::uniform,
                                 const Eigen::VectorXd& weights = {},
                                 PatchBasis basis = PatchBasis::constant,
                                 ReductionQuantity quantity = ReductionQuantity::stiffness);
/// The same from @p sole (either form): its rigid_motion_stiffness(), rigid_motion_forces() and
/// each candidate's projected_compliance (3P solves with Form::factorization, no dense C).
ReductionChoice choose_reduction(const CondensedSole& sole, double tolerance,
                                 GridSpacing spacing = GridSpacing::uniform,
                                 const Eigen::VectorXd& weights = {},
                                 PatchBasis basis = PatchBasis::constant,
                                 ReductionQuantity quantity = ReductionQuantity::stiffness);

/// Node weights for a uniform patch pressure from the nodes' consistent areas @p areas (n, m^2):
/// w_k = max(a_k, 1e-3 mean(a)) (a P2 face's vertex nodes carry no area; the floor keeps every
/// weight positive). Throws std::invalid_argument unless the areas are finite with a positive sum.
Eigen::VectorXd pressure_weights(const Eigen::VectorXd& areas);

} // namespace plantar::coupling
