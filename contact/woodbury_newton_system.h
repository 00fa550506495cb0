#pragma once
// The linear system of a semismooth Newton iteration (semismooth_newton_solver.h) for Plantar's
// form W = G G^T + blockdiag(P_j) (no general W), solved through the patches and the rigid
// factor instead of a dense LU of J_AA.
//
// On the active (not separated) contacts A, with J = A + B W block-rowed (A_k, B_k 3 x 3):
//   (J_AA + delta I) d = b   <=>   D d + B G y = b,   y = G^T d   (y: m)
// with D = A + delta I + B P block-diagonal: one dense block D_j per patch (its active contacts
// S_j: A_k + delta I on the diagonal, B_k P_kl off it) and 3 x 3 blocks A_k + delta I for the
// rigid contacts R (in no patch). D_j is invertible when P_j is positive definite; A_k of a
// sticking rigid contact is 0, so D is not, and plain Woodbury does not apply: the rigid contacts
// stay in the Schur system instead. Eliminating d_S = D_S^-1 (b_S - B_S G_S y):
//
//   K [d_R; y] = [b_R; G_S^T D_S^-1 b_S],
//   K = [ A_R + delta I     B_R G_R                        ]   (3 n_R + m square)
//       [ -G_R^T            I + sum_j G_Sj^T D_j^-1 B_Sj G_Sj ]
//
// then d_S = D_S^-1 b_S - (D_S^-1 B_S G_S) y. Cost per factorisation (operation counts):
//   sum_j [ (2/3) (3 s_j)^3 + 2 (3 s_j)^2 m + 6 s_j m^2 + 54 s_j^2 ] + (2/3) (3 n_R + m)^3,
// against (2/3) (3 n_A)^3 + 54 n_A^2 for the dense LU of J_AA: cheaper when the contacts
// spread over several patches and m is small (cost()).
//
// resize() allocates (3N + m)^2 + 3N m doubles; factorize() and solve() allocate nothing.

#include "contact/contact_problem.h"

#include <Eigen/Core>
#include <vector>

namespace plantar::contact {

class WoodburyNewtonSystem {
public:
  void resize(int max_contacts, int rigid_rank);
  /// The form it solves: no general W.
  static bool applicable(const ContactProblem& problem) { return problem.general.empty(); }
  /// Operation count of one factorisation with every contact active (see above).
  static double cost(const ContactProblem& problem);

  /// Factorises D_j and K for the active contacts @p active (n_active, ascending) with the
  /// blocks @p a_blocks, @p b_blocks (3 x 3N, contact k at columns 3k: dPhi/dr, dPhi/du) and
  /// the regularisation @p delta. Returns false when a pivot is exactly zero.
  bool factorize(const ContactProblem& problem, const int* active, int n_active,
                 const Eigen::MatrixXd& a_blocks, const Eigen::MatrixXd& b_blocks, double delta);
  /// x (3 n_active, by active position) <- (J_AA + delta I)^-1 x.
  void solve(const ContactProblem& problem, Eigen::Ref<Eigen::VectorXd> x);

private:
  struct Segment { // the active contacts of one patch: positions [start, start + count)
    int patch = 0, start = 0, count = 0;
    Eigen::Index offset = 0; // of D_j's factors in buffer_
  };
  Eigen::VectorXd buffer_;        // D_j factors, then K's: <= (3N + m)^2
  Eigen::VectorXi pivots_;        // 6N + m: D_j's (at 3 start), then K's (at 3N)
  Eigen::MatrixXd z_;             // 3N x m: D_S^-1 B_S G_S by active position
  Eigen::VectorXd work_;          // 3N + m
  Eigen::VectorXi rigid_;         // N: active positions of the rigid contacts
  Eigen::VectorXi contacts_;      // N: active contacts (copy)
  std::vector<Segment> segments_; // max_contacts (one per patch at most)
  int n_segments_ = 0, n_rigid_ = 0, n_active_ = 0, m_ = 0, max_contacts_ = 0;
  Eigen::Index k_offset_ = 0;
};

} // namespace plantar::contact
