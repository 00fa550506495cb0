#pragma once
// Settings and result of a frictional contact solve (plain structs).

#include <string>

namespace plantar::contact {

enum class ContactSolverType {
  gauss_seidel, ///< nonsmooth Gauss-Seidel, exact 3x3 local solves (baseline)
  admm,         ///< ADMM with proximal term and adaptive rho (dense/coupled, ill-conditioned cases)
  newton,       ///< semismooth Newton on the Alart-Curnier function (semismooth_newton_solver.h)
  automatic,    ///< Gauss-Seidel while it converges fast, then Newton (auto_solver.h)
};

/// How semismooth Newton solves its linear system (J_AA + delta I) d_A = -Phi_A - ... each
/// iteration (semismooth_newton_solver.h). All give the same step up to round-off.
enum class NewtonLinearSolve {
  automatic, ///< the cheapest by operation counts (NewtonLinearCost, semismooth_newton_solver.h)
  dense,     ///< dense LU of J_AA (any W)
  sparse,    ///< sparse LU of the block-sparse J_AA (a general W stored sparse, no G, no patches)
  woodbury,  ///< per-patch LU plus a Schur system of size 3 n_rigid + m (W = G G^T + patches)
};

/// Why ContactSolverType::automatic left Gauss-Seidel for Newton.
enum class SwitchReason {
  none,    ///< no switch: Gauss-Seidel finished (or another solver was chosen)
  slow,    ///< GS's measured rate predicted more than auto_switch_sweeps further sweeps
  stalled, ///< GS's residual did not decrease over a check interval
  budget,  ///< GS used max_iterations sweeps without converging
  failed,  ///< GS produced non-finite values (Newton restarted from zero)
};

struct SolverSettings {
  ContactSolverType solver = ContactSolverType::admm;
  /// Stop when the natural-map residual (m/s, max over contacts) is <= this. Range (0, inf).
  double tolerance = 1e-9;
  /// Sweeps (Gauss-Seidel) or iterations (ADMM). Range [1, inf).
  int max_iterations = 500;
  /// Start from the impulses passed in (projected onto the cones) instead of zero.
  bool warm_start = true;
  /// Gauss-Seidel: enumerate every solution of each local problem (LocalSearch::all, the
  /// 64-point scan on every local solve) so that non-unique ones are counted; false: only the
  /// preferred solution (LocalSearch::first), non-uniqueness not detected. Costs in
  /// docs/contact.md.
  bool enumerate_local_solutions = false;
  /// Gauss-Seidel: a contact whose natural-map residual at its turn in a sweep is <=
  /// sweep_skip * tolerance keeps its impulse for that sweep (no local solve, no column
  /// update); the stopping test still asks every contact for <= tolerance. 0 updates every
  /// contact. Range [0, 1).
  double sweep_skip = 0.0;
  /// Before iterating, solve directly on the warm start's prediction: contacts with p_n > 0
  /// strictly inside the cone sticking, those on the cone sliding (p_t = mu p_n d, d the warm
  /// start's direction, updated to minus the slip's), the others separated (p = 0). Needs every
  /// contact on a patch with its rigid structure (ContactProblem::patch_levers: lever,
  /// lever_map_valid, version). W_AA p_A = -(v_free + b e_n)_A + slip by Woodbury over the kept
  /// Cholesky factors of the active sole blocks (updated node by node when the set changes); the
  /// result is kept when it lies in the cones and meets the tolerance (then it is an exact
  /// solution), else the iterative solver starts from it, projected onto the cones. A problem with
  /// no contact on a patch (W = G G^T, rigid contacts) takes RigidStickingSolver instead
  /// (rigid_sticking_solver.h: the sticking impulses nearest the warm start by a pseudo-inverse,
  /// with active-set rounds), whose refused candidates are dropped (the iteration starts from the
  /// warm start).
  bool sticking_direct = true;
  /// Compliant patches: active sets the direct solve tries before handing over to the
  /// iterative solver (sticking_solver.cc: a sticking contact outside its cone slides, one
  /// pulled off separates, a sliding one that slips along its friction sticks, a separated
  /// one closing sticks). 1 tries the warm start's prediction only. Range [1, inf).
  int sticking_rounds = 8;
  /// ADMM: initial rho = rho_scale * mean diagonal of W. Range (0, inf).
  double rho_scale = 1.0;
  /// ADMM: proximal weight eta = proximal_scale * mean diagonal of W. Range [0, inf).
  double proximal_scale = 1e-6;
  /// ADMM: rho is reconsidered every this many iterations (needs a refactorisation). Range [1,
  /// inf).
  int rho_update_interval = 8;
  /// ADMM: rho changes when the primal and dual residuals differ by more than this ratio. Range (1,
  /// inf).
  double rho_update_ratio = 5.0;
  /// ADMM: at most this many factorisations per solve. Range [1, inf).
  int max_factorizations = 60;
  /// ADMM: start from the previous solve's final rho (lets the patch factorisation be reused).
  bool warm_rho = true;
  /// Automatic: Gauss-Seidel's rate is measured over this many sweeps. Range [1, inf).
  int auto_check_interval = 10;
  /// Automatic: switch to Newton when the measured rate rho (residual ratio per sweep) predicts
  /// more than this many further sweeps to the tolerance, log(tol / r) / log(rho), and those
  /// sweeps cost more than auto_newton_iterations Newton iterations (operation counts, see
  /// auto_solver.h). Range [1, inf).
  double auto_switch_sweeps = 100.0;
  /// Automatic: Newton iterations expected after a switch, in the cost comparison. Range [1, inf).
  double auto_newton_iterations = 20.0;
  /// Newton (and automatic): the linear solve of each iteration; a form the problem does not
  /// have (sparse without a sparse general W, woodbury with one) falls back to dense.
  NewtonLinearSolve newton_linear_solve = NewtonLinearSolve::automatic;
  /// Newton: stop (status max_iterations) once this many iterations have passed without the
  /// residual falling below half its lowest value at the start of them; 0 never stops early.
  /// Range [0, inf).
  int newton_stall_iterations = 0;
  /// Newton: rho_k = newton_rho_scale * 3 / trace(W_kk) in the Alart-Curnier function
  /// (semismooth_newton_solver.h). Range (0, inf).
  double newton_rho_scale = 1.0;
  /// Automatic: newton_stall_iterations of Newton from Gauss-Seidel's iterate (then Newton
  /// restarts from zero, auto_solver.h); 0 lets it use half the budget. Range [0, inf).
  int auto_newton_stall_iterations = 20;

  /// Throws std::invalid_argument naming the field, its value and the allowed range.
  void validate() const;
};

enum class SolverStatus {
  converged,      ///< residual <= tolerance
  max_iterations, ///< stopped at max_iterations with residual > tolerance
  non_finite,     ///< NaN or Inf appeared; impulses are reset to zero
};

/// What became of the direct solve on the warm start's active set (SolverSettings::
/// sticking_direct) in one solve.
enum class DirectAttempt {
  not_tried,        ///< off, no warm start, no patch structure, or no contact predicted sticking
  accepted,         ///< its candidate is the solution (SolverResult::direct)
  refused_cone,     ///< a contact predicted sticking left its cone: the iteration went on
  refused_residual, ///< all in their cones, but the residual was above the tolerance
  failed,           ///< C_AA or the capacitance not positive definite, or a non-finite candidate
};

struct SolverResult {
  SolverStatus status = SolverStatus::max_iterations;
  int iterations = 0;
  /// Natural-map (De Saxce) complementarity residual, max over contacts, m/s.
  double residual = 0.0;
  /// Gauss-Seidel: contacts whose last local problem had several solutions
  /// (indeterminate, e.g. Painleve; counted only with enumerate_local_solutions) or none
  /// (then a projection step was used).
  int n_nonunique_local = 0;
  int n_failed_local = 0;
  /// ADMM: factorisations done and final rho (m/(N s^2)).
  int n_factorizations = 0;
  double rho = 0.0;
  /// The solution came from the direct solve on the warm start's active set (iterations = 0).
  bool direct = false;
  DirectAttempt direct_attempt = DirectAttempt::not_tried;
  /// Gauss-Seidel: exact local solves done, summed over the sweeps (contacts left by the sweep
  /// skip not counted).
  int n_local_solves = 0;
  /// The solver whose iterate was returned (settings.solver, or for automatic gauss_seidel or
  /// newton).
  ContactSolverType finished_by = ContactSolverType::gauss_seidel;
  /// Automatic: why it switched to Newton, after how many GS sweeps (iterations counts both),
  /// and GS's measured residual ratio per sweep over the last check interval.
  SwitchReason switch_reason = SwitchReason::none;
  int switch_iteration = 0;
  double switch_rate = 0.0;
  /// Newton: the linear solve it used (never automatic after a Newton iteration).
  NewtonLinearSolve newton_linear_solve = NewtonLinearSolve::automatic;
  bool converged() const { return status == SolverStatus::converged; }
};

const char* to_string(SolverStatus status);
const char* to_string(ContactSolverType type);
const char* to_string(DirectAttempt attempt);
const char* to_string(SwitchReason reason);
const char* to_string(NewtonLinearSolve solve);

/// Throws std::runtime_error with solver, status, iterations, residual and
/// tolerance unless @p result converged. @p context names the caller (e.g. "step 120").
void throw_if_not_converged(const SolverResult& result, const SolverSettings& settings,
                            const std::string& context);

} // namespace plantar::contact
