#pragma once
// Test/benchmark fixture: compliance of contact nodes on an elastic half-space.
//   normal   (Boussinesq): C_nn(i,j) = (1 - nu^2) / (pi E r_ij)
//   tangent  (Cerruti):    C_xx(i,j) = (1 + nu) / (pi E r) [(1 - nu) + nu x^2/r^2],
//                          C_yy likewise with y, C_xy = (1 + nu) nu x y / (pi E r^3)
//   self terms: centre displacement of a uniformly loaded square of side a
//   (the node's tributary area a^2): 4 ln(1 + sqrt 2) (1 - nu^2) / (pi E a)
//   normal, with (1 - nu^2) replaced by (1 + nu)(1 - nu/2) (angle average of
//   the Cerruti kernel) tangentially.
// The normal-tangential coupling of the half-space, proportional to (1 - 2 nu),
// is neglected (exact for nu = 0.5). Frame per node: (n = z, t1 = x, t2 = y).

#include <Eigen/Core>
#include <vector>

namespace plantar::contact::test {

/// n_side x n_side nodes with spacing a, centred at the origin; (n^2 x 2) positions, m.
Eigen::MatrixXd square_grid(int n_side, double spacing);
/// n_x x n_y nodes with spacing a, centred at the origin; (n_x n_y x 2) positions, m.
Eigen::MatrixXd rectangular_grid(int n_x, int n_y, double spacing);

/// (3 n x 3 n) compliance, m/N, for nodes at @p positions (n x 2, m), node
/// spacing @p spacing (m), Young's modulus E (Pa) and Poisson ratio nu.
Eigen::MatrixXd boussinesq_compliance(const Eigen::MatrixXd& positions, double spacing,
                                      double young, double poisson);

} // namespace plantar::contact::test
