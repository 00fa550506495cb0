#pragma once
// Exact solution of the one-contact problem used by the Gauss-Seidel sweep:
//
//   v = A p + q,   p in K_mu,   v + (b + mu ||v_t||) e_n in K_mu^*,   p . (v + ...) = 0,
//
// A (3x3, symmetric positive semi-definite) the diagonal block W_kk, q the
// velocity from the free motion and all other contacts. Every solution is one
// of three kinds, each found exactly:
//   separation: p = 0, valid iff q_n + b >= 0;
//   sticking:   p = -A^-1 (q + b e_n), valid iff p in K_mu;
//   sliding:    p = p_n (1, mu cos phi, mu sin phi), v_n + b = 0 and
//               v_t = -alpha (cos phi, sin phi), alpha >= 0: the angle phi is a
//               root of a trigonometric polynomial of degree 2 (at most four
//               roots), bracketed on a 64-point grid and refined by regula falsi (Illinois)
//               to round-off; for each root p_n follows in closed form.
// For a positive definite A a solution exists; it is unique for small mu but
// may not be for large mu (Painleve-type cases): with LocalSearch::all,
// n_solutions reports how many distinct solutions were found.
// LocalSearch::first returns the same choice without the enumeration: it
// stops at a valid separation or sticking solution (the preferred kinds), and
// finds a sliding solution by Newton's method on phi started from the previous
// impulse's (else the sticking candidate's) direction, falling back to the
// grid scan when Newton fails; n_solutions is then 1 (non-uniqueness is not
// detected) and, with several sliding solutions, the one Newton reaches.

#include <Eigen/Core>

namespace plantar::contact {

/// How many solutions the local solve looks for.
enum class LocalSearch {
  first, ///< the preferred solution only (fast: about 20 ns when sticking or separating)
  all,   ///< every solution (the 64-point scan always runs, about 1 us)
};

struct LocalSolution {
  Eigen::Vector3d impulse = Eigen::Vector3d::Zero(); ///< chosen solution, N s
  int n_solutions = 0; ///< distinct valid solutions found (0: none, >1: non-unique)
  enum class Kind { none, separation, sticking, sliding } kind = Kind::none;
};

/// Solves the one-contact problem above; prefers separation, then sticking,
/// then the sliding solution closest to @p previous when several are valid.
/// @param delassus A (3x3), m/(N s). @param velocity_rest q (3), m/s.
/// @param normal_bias b, m/s. @param mu >= 0. @param previous p before the update.
/// @param search LocalSearch::all (enumerate) or ::first (see above).
/// @param inverse A^-1 from local_inverse() when the caller keeps it across calls with the
/// same A (nullptr: computed here). Does not allocate.
LocalSolution solve_local_contact(const Eigen::Matrix3d& delassus,
                                  const Eigen::Vector3d& velocity_rest, double normal_bias,
                                  double mu, const Eigen::Vector3d& previous,
                                  LocalSearch search = LocalSearch::all,
                                  const Eigen::Matrix3d* inverse = nullptr);

/// A^-1 for the sticking candidate p = -A^-1 (q + b e_n) when A is invertible
/// (|det A| > 1e-13 max|A_ii|^3); false otherwise (no sticking candidate).
bool local_inverse(const Eigen::Matrix3d& delassus, Eigen::Matrix3d& inverse);

} // namespace plantar::contact
