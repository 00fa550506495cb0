#pragma once
// Static frictional contact of a sole on the ground z = z_g, on distributed PETSc (issue 26):
// the full-resolution reference for every condensed or reduced sole.
//
// The sole (a hexahedral mesh, parallel::distributed::Triangulation built from the coarse mesh
// and refined globally; Q1 or Q2, linear elasticity with its MaterialTable) is attached by its
// top face to a rigid foot with the prescribed small rigid displacement
//   u(x) = t + theta x (x - p)              (t in m, theta a rotation vector in rad, p in m);
// the nodes k of its bottom face touch the ground. With lambda_k = (K u)_k the nodal force of
// the ground on node k (N; sole frame x, y, z; no other load), the gap g_k = z_k + u_z,k - z_g
// (m) and the slip s_k = (u_x,k, u_y,k) (m, measured from the unloaded state: one load step),
// Signorini and Coulomb's law read per node:
//   lambda_n >= 0, g >= 0, lambda_n g = 0;   |lambda_t| <= mu lambda_n,
//   s = 0 if |lambda_t| < mu lambda_n, else lambda_t = -mu lambda_n s / |s|.
// They are solved by the semismooth Newton (primal-dual active set) method of Hueber, Stadler
// and Wohlmuth (SIAM J. Sci. Comput. 30, 2008) with nodal complementarity functions
//   xi_n = lambda_n - c g,  xi_t = lambda_t - c s,   (c: mean diagonal of K on the contact dofs)
//   C_n = lambda_n - max(0, xi_n),
//   C_t = max(mu xi_n+, |xi_t|) lambda_t - mu xi_n+ xi_t,
// node states: separated (xi_n <= 0: lambda = 0), stick (|xi_t| < mu xi_n: g = 0, s = 0),
// slip (g = 0, the linearised C_t = 0 with lambda_t in the Jacobian projected onto the cone).
// Each Newton system is K with rows replaced: Dirichlet rows (top nodes; g = 0; s = 0) and, for
// slip nodes, the two rows of the linearised C_t (combinations of the node's rows of K), solved
// by MUMPS (PETSc, default) for the new u, or by GMRES for the increment du (A du = b - A u: the
// right-hand side is the Newton system's residual, so that a relative tolerance stays
// meaningful as u converges), preconditioned by BoomerAMG or by PETSc's GAMG (smoothed
// aggregation on 3 x 3 nodal blocks with the six rigid-body modes from the dof coordinates as
// its near null space). The iteration stops when
//   r = max_k |(C_n, P_t)_k| <= tolerance max(max_k |lambda_k|, c x 1 nm),
//   P_t = lambda_t - proj_{|.| <= mu xi_n+}(xi_t)     (N; 0 iff Coulomb's law holds),
// and throws std::runtime_error naming the iteration and residual after max_iterations.
// Simplex meshes are refused (p4est refines hexahedra only).

#include "fem/material_table.h"

#include <deal.II/base/index_set.h>
#include <deal.II/base/point.h>
#include <deal.II/base/tensor.h>
#include <deal.II/distributed/tria.h>
#include <deal.II/dofs/dof_handler.h>
#include <deal.II/fe/fe_system.h>
#include <deal.II/fe/mapping_q.h>
#include <deal.II/lac/petsc_sparse_matrix.h>
#include <deal.II/lac/petsc_vector.h>

#include <mpi.h>
#include <petscksp.h>

#include <array>
#include <string>
#include <vector>

namespace plantar::fem {

/// A small rigid displacement of the foot: u(x) = translation + rotation x (x - center).
struct RigidMotion {
  dealii::Tensor<1, 3> translation; ///< t, m
  dealii::Tensor<1, 3> rotation;    ///< theta, rad (rotation vector, linearised: |theta| << 1)
  dealii::Point<3> center;          ///< p, m, mesh frame
  /// u(x), m.
  dealii::Tensor<1, 3> displacement(const dealii::Point<3>& x) const;
};

/// Linear solver of each Newton system.
enum class ContactLinearSolver {
  mumps,      ///< sparse direct LU (MUMPS through PETSc)
  gmres_amg,  ///< GMRES(200) + BoomerAMG on the increment, relative tolerance linear_tolerance
  gmres_gamg, ///< GMRES(200) + GAMG with the rigid-body modes, on the increment, same tolerance
};

struct DistributedContactSettings {
  dealii::types::boundary_id attached_boundary = 0; ///< the sole's top (on the foot)
  dealii::types::boundary_id contact_boundary = 1;  ///< the sole's bottom (on the ground)
  unsigned int degree = 1;                          ///< Q1 or Q2
  unsigned int refinements = 0;                     ///< global refinements of the coarse mesh
  double friction = 0.5;                            ///< mu, [0, 10]
  double ground_height = 0;                         ///< z_g, m, mesh frame
  double tolerance = 1e-10;                         ///< relative, (0, 1e-2]
  unsigned int max_iterations = 50;                 ///< Newton iterations, [1, 1000]
  ContactLinearSolver linear_solver = ContactLinearSolver::mumps;
  double linear_tolerance = 1e-8; ///< GMRES: ||b - A u - A du|| <= this ||b - A u||, (0, 1)
  /// Throws std::invalid_argument naming the field, its value and the allowed range.
  void validate() const;
};

enum class NodeState { separated, stick, slip };

/// One contact node after a solve (sole frame).
struct ContactNode {
  dealii::Point<3> position;         ///< m, unloaded
  dealii::Tensor<1, 3> force;        ///< lambda, N, of the ground on the sole
  dealii::Tensor<1, 3> displacement; ///< u, m
  double area = 0;                   ///< A_k, m^2: its shape function's integral on the face
  NodeState state = NodeState::separated;
};

/// Figures of the last solve (global over ranks).
struct ContactSolveReport {
  unsigned int iterations = 0; ///< Newton iterations (linear solves)
  double residual = 0;         ///< r / max_k |lambda_k| at the end
  unsigned int n_separated = 0, n_stick = 0, n_slip = 0;
  unsigned int linear_iterations = 0;  ///< GMRES: total over the Newton iterations
  double solve_time = 0;               ///< s, wall, whole solve (this rank)
  std::vector<double> iteration_times; ///< s, wall, each Newton iteration (this rank)
};

class DistributedContact {
public:
  /// Distributes @p coarse (hexahedra; copied) over @p communicator, refines it
  /// settings.refinements times, distributes Q_degree dofs and assembles K (N/m).
  /// @throws std::invalid_argument for a simplex mesh or bad settings, or if a boundary id holds
  ///   no face.
  DistributedContact(MPI_Comm communicator, const dealii::Triangulation<3>& coarse,
                     const MaterialTable& materials, const DistributedContactSettings& settings);
  ~DistributedContact();
  DistributedContact(const DistributedContact&) = delete;
  DistributedContact& operator=(const DistributedContact&) = delete;

  /// Solves the contact problem for the foot motion @p foot (see above); the previous solution
  /// is not used. @throws std::runtime_error "static contact: ... after N iterations ..." if the
  /// residual is above the tolerance after max_iterations, or if a linear solve fails.
  const ContactSolveReport& solve(const RigidMotion& foot);

  /// Every contact node (all ranks), ordered by position (x, then y, then z, rounded to 1e-9 m):
  /// the same order whatever the partition. Collective.
  std::vector<ContactNode> gather_contact_nodes() const;
  /// Force of the foot on the sole, sum of (K u) over the top nodes (N). Collective.
  dealii::Tensor<1, 3> foot_force() const;
  /// Its moment about @p point (N m). Collective.
  dealii::Tensor<1, 3> foot_moment(const dealii::Point<3>& point) const;
  /// Sum of the contact forces lambda_k (N). Collective.
  dealii::Tensor<1, 3> ground_force() const;
  /// max_k lambda_n,k / A_k, the largest nodal contact pressure (Pa) with A_k the node's
  /// lumped area (integral of its shape function over the contact face). Collective.
  double max_pressure() const;

  dealii::types::global_dof_index n_dofs() const { return dof_handler_.n_dofs(); }
  unsigned int n_contact_nodes() const { return n_contact_nodes_; }
  unsigned int n_cells() const { return triangulation_.n_global_active_cells(); }
  const dealii::DoFHandler<3>& dof_handler() const { return dof_handler_; }
  const dealii::Mapping<3>& mapping() const { return mapping_; }
  const MaterialTable& materials() const { return materials_; }
  const dealii::parallel::distributed::Triangulation<3>& triangulation() const {
    return triangulation_;
  }
  MPI_Comm communicator() const { return communicator_; }
  /// u (m) with ghost entries (locally relevant dofs), for output.
  const dealii::PETScWrappers::MPI::Vector& ghosted_solution() const { return ghosted_solution_; }
  /// Nodal contact pressure lambda_n / A_k (Pa) on the contact nodes' z dofs and their
  /// tangential tractions lambda_t / A_k on their x, y dofs, 0 elsewhere; ghosted.
  const dealii::PETScWrappers::MPI::Vector& ghosted_traction() const { return ghosted_traction_; }
  double assembly_time() const { return assembly_time_; } ///< s, wall (this rank)
  double setup_time() const { return setup_time_; }       ///< s, wall (this rank)
  const ContactSolveReport& report() const { return report_; }

  /// A node of a boundary owned by this rank: its x, y, z dofs and unloaded position.
  struct Node {
    std::array<dealii::types::global_dof_index, 3> dofs;
    dealii::Point<3> position; ///< m
  };
  /// K (N/m, n_dofs x n_dofs, no boundary condition), distributed by owned dofs.
  const dealii::PETScWrappers::MPI::SparseMatrix& stiffness_matrix() const { return stiffness_; }
  /// The bottom (contact) nodes whose dofs this rank owns, sorted by x dof.
  const std::vector<Node>& owned_contact_nodes() const { return contact_nodes_; }
  /// The top (attached) nodes whose dofs this rank owns, sorted by x dof.
  const std::vector<Node>& owned_attached_nodes() const { return top_nodes_; }

private:
  std::vector<Node> owned_boundary_nodes(dealii::types::boundary_id boundary) const;
  void setup();
  void assemble();
  void lumped_areas();
  /// Evaluates lambda = K u, the node states and the residual of the current u.
  double evaluate();
  void build_system(const RigidMotion& foot);
  /// GAMG: checks the dofs come in x, y, z nodes, attaches the rigid-body modes from their
  /// coordinates to the Newton matrix (block size 3) and creates the solver.
  void gamg_setup();
  void linear_solve();
  /// GMRES on the increment: solution_ += du, A du = rhs_ - A solution_.
  void iterative_solve();

  MPI_Comm communicator_;
  const MaterialTable& materials_;
  DistributedContactSettings settings_;
  dealii::parallel::distributed::Triangulation<3> triangulation_;
  dealii::FESystem<3> fe_;
  dealii::MappingQ<3> mapping_;
  dealii::DoFHandler<3> dof_handler_;
  dealii::IndexSet owned_dofs_, relevant_dofs_;
  dealii::PETScWrappers::MPI::SparseMatrix stiffness_, system_;
  dealii::PETScWrappers::MPI::Vector solution_, forces_, rhs_, constrained_values_;
  dealii::PETScWrappers::MPI::Vector increment_, newton_residual_; ///< GMRES only
  KSP ksp_ = nullptr; ///< GMRES + GAMG, kept over the solves (gmres_gamg only)
  dealii::PETScWrappers::MPI::Vector ghosted_solution_, ghosted_traction_;
  std::vector<Node> contact_nodes_, top_nodes_;
  std::vector<double> contact_areas_;     ///< A_k per owned contact node, m^2
  std::vector<NodeState> states_;         ///< per owned contact node
  std::vector<std::array<double, 6>> xi_; ///< per owned contact node: xi_n, xi_t (2), lambda
  unsigned int n_contact_nodes_ = 0;
  double complementarity_scale_ = 0; ///< c, N/m
  double assembly_time_ = 0, setup_time_ = 0;
  ContactSolveReport report_;
};

/// "mumps", "gmres amg" or "gmres gamg"; throws std::invalid_argument naming @p parameter
/// otherwise.
ContactLinearSolver parse_contact_linear_solver(const std::string& text,
                                                const std::string& parameter);

} // namespace plantar::fem
