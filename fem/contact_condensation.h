#pragma once
// Condensation of a sole's stiffness onto its contact nodes, written once for
// the linear sole (coupling::CondensedSole: K, CHOLMOD) and the hyperelastic
// one (fem::NonlinearSole: the tangent K_T(u), UMFPACK)
// (David et al. 2008, eq. 11; Duriez et al. 2006).
//
// The free dofs of K u = f (attached nodes: u = 0, removed) split into the
// contact dofs c (3 n_c, node-major: 3k + d is component d of contact node k)
// and the others n, which carry no load:
//
//   K_c = K_cc - K_cn K_nn^-1 K_nc        (Schur complement, N/m)
//   C   = K_c^-1 = [K^-1]_cc              (contact compliance, m/N)
//
// The second form is what is computed: K x_j = e_j for each contact dof j
// (unit loads, in blocks of right-hand sides), keeping the contact rows of
// x_j: C(i, j) = x_j(i). Then C is checked (finite, not zero) and symmetrized,
// C <- (C + C^T) / 2, after its raw asymmetry is recorded.
//
// Here in fem/ (deal.II only, no Eigen): callers pass a block solver over
// their own numbering and a contiguous n x n buffer for C.

#include <deal.II/dofs/dof_handler.h>
#include <deal.II/lac/affine_constraints.h>

#include <array>
#include <functional>
#include <string>
#include <vector>

namespace plantar::fem {

/// Solves K X = B for @p count right-hand sides: @p rhs (B) and @p solution (X)
/// are (n_unknowns x count) column-major, column j at offset j n_unknowns.
using BlockSolve = std::function<void(const double* rhs, double* solution, unsigned int count)>;

/// The nodes of the faces with boundary id @p boundary: their global dof
/// indices (x, y, z), sorted by the x dof (deal.II's dof order). Node-major:
/// this order is the contact order 3k + d of the condensation.
/// @throws std::logic_error if a face's dofs are not grouped x, y, z per node.
std::vector<std::array<dealii::types::global_dof_index, 3>>
boundary_nodes(const dealii::DoFHandler<3>& dof_handler, dealii::types::boundary_id boundary);

/// Checks that no dof of the contact nodes @p nodes is constrained (the
/// contact face must not touch the attached face @p attached_boundary).
/// @param support_points  (n_dofs) support points (m) of @p constraints' dofs.
/// @throws std::invalid_argument "<who>: contact node k at (x y z) m lies on the
///   attached boundary <id> ...".
void check_contact_nodes_free(
    const std::vector<std::array<dealii::types::global_dof_index, 3>>& nodes,
    const dealii::AffineConstraints<double>& constraints,
    const std::vector<dealii::Point<3>>& support_points,
    dealii::types::boundary_id attached_boundary, const std::string& who);

/// The contact block of the inverse, C = [K^-1]_cc (see above):
///   C(i, j) = x_j(contact_index[i]),  K x_j = e_{contact_index[j]},
/// solved @p block_size columns at a time by @p solve.
/// @param contact_index  (n = 3 n_c) position of contact dof i (node-major)
///        in the solver's numbering, each < @p n_unknowns.
/// @param compliance  output, n x n contiguous (m/N if K is in N/m): column j
///        is written at compliance + j n (column-major; into a row-major buffer
///        this writes C^T, which symmetrize() maps onto the same result).
/// Not symmetrized. Allocates 2 n_unknowns block_size doubles.
/// @throws std::runtime_error "<who>: the contact compliance C ..." if an entry
///   is not finite or C is zero.
void contact_block_of_inverse(const std::vector<unsigned int>& contact_index,
                              unsigned int n_unknowns, unsigned int block_size,
                              const BlockSolve& solve, double* compliance, const std::string& who);

/// max_ij |A_ij - A_ji| / max_ij |A_ij| of the n x n contiguous matrix @p a (0
/// for a zero matrix). fem/'s copy of contact::relative_asymmetry (contact/
/// symmetry.h, Eigen), same arithmetic: fem/ links neither contact/ nor Eigen.
double relative_asymmetry(const double* a, unsigned int n);

/// A <- (A + A^T) / 2 in place, n x n contiguous (either storage order).
void symmetrize(double* a, unsigned int n);

} // namespace plantar::fem
