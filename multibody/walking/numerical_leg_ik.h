// Numerical inverse kinematics of a serial chain of 1-DoF joints (a 6-DoF leg of any geometry)
// on SE(3): damped Gauss-Newton (Levenberg-Marquardt) with joint limits by an active set and
// projection, and a backtracking line search. Uses plantar_multibody's kinematics and Jacobians.
#pragma once

#include "multibody/data.h"
#include "multibody/model.h"
#include "multibody/spatial.h"

#include <Eigen/Cholesky>
#include <Eigen/Core>
#include <vector>

namespace plantar::walking {

/// Settings of NumericalLegIk. Lengths in m, angles in rad (a prismatic joint's coordinate in m).
struct NumericalIkSettings {
  double position_tolerance = 1e-10; ///< m: converged when |p - p*| <= this ...
  double rotation_tolerance = 1e-10; ///< rad: ... and the angle of R R*^T <= this
  int max_iterations = 100;          ///< Gauss-Newton steps per start before giving it up, >= 1
  /// mu in the Levenberg-Marquardt damping lambda = mu |e|^2 + lambda_min (Sugihara 2011):
  /// large errors give short, gradient-like steps, small errors Gauss-Newton steps (quadratic
  /// convergence). SI units (|e|^2 mixes m^2 and rad^2), >= 0.
  double damping = 1.0;
  /// lambda_min: keeps J^T J + lambda 1 positive definite at singular poses (straight knee,
  /// redundant chains), > 0.
  double min_damping = 1e-12;
  /// Largest change of one coordinate in one step (rad or m); longer steps are scaled down as a
  /// whole, keeping their direction, > 0.
  double max_step = 0.5;
  /// A step whose largest coordinate change is below this while not converged means a
  /// stationary point of |e|^2 within the limits (target out of reach, or past a limit): fail,
  /// > 0.
  double step_tolerance = 1e-14;
  /// Further starts tried when the descent from the warm start fails (a local minimum of |e|
  /// within the limits: typically a knee that a step took across the straight-leg singularity to
  /// its backward limit, or a target rotated by about pi from the start): the centre of the
  /// limits, then deterministic pseudo-random points uniform within them. Coordinates with an
  /// infinite limit keep the warm start. 0: warm start only, >= 0.
  int max_restarts = 16;
};

/// Outcome of a successful NumericalLegIk::solve.
struct NumericalIkReport {
  int iterations = 0; ///< Gauss-Newton steps taken, all starts (0: the warm start was a solution)
  int restarts = 0;   ///< starts tried after the warm start (0: converged from the warm start)
  double position_error = 0.0; ///< |p - p*| at the solution, m
  double rotation_error = 0.0; ///< angle of R R*^T at the solution, rad
};

/// Inverse kinematics of one frame by the coordinates of a chain of 1-DoF joints.
///
/// Error (6, world axes, at the frame origin, consistent with frame_jacobian's
/// LOCAL_WORLD_ALIGNED convention): for the frame pose (R, p) and the target (R*, p*)
///   e = [p - p*; log3(R R*^T)]   (m; rad),
/// with the Jacobian with respect to the chain coordinates x (6 x n)
///   E = de/dx = [J_lin; J_l^-1(log3(R R*^T)) J_ang],
/// J = frame_jacobian restricted to the chain's columns, J_l^-1 the inverse left Jacobian of
/// SO(3) (spatial.h; d/dt R R*^T = [w]x R R*^T).
///
/// Iteration (Levenberg-Marquardt with Sugihara's damping: "Solvability-unconcerned inverse
/// kinematics by the Levenberg-Marquardt method", IEEE T-RO 27(5), 2011; bounds by Bertsekas'
/// projected Newton method: "Projected Newton methods for optimization problems with simple
/// constraints", SIAM J. Control Optim. 20(2), 1982), all coordinates x within [l, u]:
///   g = E^T e,  H = E^T E + (mu |e|^2 + lambda_min) 1,
///   active set A: x_k within eps = min(1e-3, |x - P(x - g)|_inf) of a limit with g_k pointing
///     out of it; then, re-solving, coordinates at a limit whose step points out;
///   H_FF d_F = -g_F on the free coordinates F, d_k = -g_k / H_kk on A;
///   d scaled down to |d|_inf <= max_step;
///   x+ = P(x + alpha d), P the clamp onto [l, u], alpha = 1, 1/2, 1/4, ... the first with
///     |e(x+)|^2 / 2 < |e(x)|^2 / 2 + 1e-4 g^T (x+ - x)  (or converged);
///   stop: converged; |P(x + d) - x|_inf <= step_tolerance or no alpha >= 1e-12 decreases
///     |e| (a stationary point within the limits); max_iterations.
/// Every iterate is inside the limits. If the descent from the warm start stops without
/// converging, up to max_restarts further starts are tried (see NumericalIkSettings).
///
/// Keeps a reference to the model (which must outlive the solver) and owns its Data and
/// workspaces: solve() allocates nothing (except to build the message of an exception).
class NumericalLegIk {
public:
  /// @param joints model joint indices of the chain (each a 1-DoF revolute or prismatic joint, an
  ///   ancestor of the frame's body), in any order; n = joints.size() >= 1, no duplicates.
  /// @param frame model frame index of the end effector (e.g. the sole frame).
  /// @throws std::invalid_argument naming the joint or frame if an index is out of range, a joint
  ///   is not 1-DoF, appears twice or does not move the frame, or if a setting is out of range.
  NumericalLegIk(const multibody::Model& model, std::vector<int> joints, int frame,
                 NumericalIkSettings settings = {});

  /// Solves frame_placement(q) = target by changing only the chain's coordinates of q.
  /// @param q size nq; in: the warm start, which also fixes every other coordinate (including
  ///   the floating base); a chain coordinate outside its limits is first clamped into them.
  ///   Out: the solution, inside the limits. Unchanged if solve throws.
  /// @param target world pose of the frame (frame -> world).
  /// @return iterations and the final errors (<= the tolerances).
  /// @throws std::runtime_error if no start converges (max_iterations reached, or a stationary
  ///   point of the error within the limits: target out of reach or past a joint limit), naming
  ///   the frame, the target (position, m, and roll-pitch-yaw, rad), the residual errors and the
  ///   joints at a limit (with the limit) of the start that came closest.
  ///   std::invalid_argument if q has the wrong size.
  NumericalIkReport solve(Eigen::Ref<Eigen::VectorXd> q, const multibody::SE3& target);

  /// The error e (6) and its Jacobian E (6 x n, columns in the order of joints()) at q (size nq),
  /// as defined above. Used by solve(); public to check E against finite differences.
  void error_and_jacobian(const Eigen::Ref<const Eigen::VectorXd>& q, const multibody::SE3& target,
                          multibody::Vector6d& error, Eigen::Ref<Eigen::MatrixXd> jacobian);

  const std::vector<int>& joints() const { return joints_; }
  int frame() const { return frame_; }
  const NumericalIkSettings& settings() const { return settings_; }

private:
  enum class Stop { converged, max_iterations, stationary, line_search };
  /// Coordinate k of restart number `start` >= 1 as a fraction of its range: 1/2 for the first
  /// (the centre of the limits), then deterministic pseudo-random numbers in [0, 1).
  static double spread_fraction(int start, int k);
  /// Iterates from x_ (= q_work_'s chain coordinates) until a stop; counts the steps in
  /// `iterations`; leaves the last iterate in x_ and q_work_ and its error in `error`.
  Stop descend(const multibody::SE3& target, multibody::Vector6d& error, int& iterations);
  /// e at data_'s current kinematics.
  void compute_error(const multibody::SE3& target, multibody::Vector6d& error) const;
  /// E at data_'s current kinematics, given e (fills data_.jacobian and jacobian_).
  void compute_jacobian(const multibody::Vector6d& error);
  bool converged(const multibody::Vector6d& error) const;
  [[noreturn]] void fail(const char* reason, const multibody::SE3& target,
                         const multibody::Vector6d& error, int iterations, int starts) const;

  const multibody::Model& model_;
  std::vector<int> joints_; ///< model joint indices
  int frame_;
  NumericalIkSettings settings_;
  std::vector<int> idx_q_, idx_v_; ///< the chain's coordinate indices in q and v
  Eigen::VectorXd lower_, upper_;  ///< the chain's limits (n)
  bool restartable_ = false;       ///< some coordinate has finite limits (restarts differ)

  multibody::Data data_;
  // Workspaces, sized by the constructor.
  Eigen::VectorXd q_work_, q_trial_;                   ///< nq
  Eigen::MatrixXd jacobian_;                           ///< E, 6 x n
  Eigen::MatrixXd hessian_;                            ///< H (reduced to F), n x n
  Eigen::VectorXd x_, best_x_, gradient_, rhs_, step_; ///< n
  std::vector<char> active_;                           ///< n, 1 if in the active set
  Eigen::LLT<Eigen::MatrixXd> llt_;                    ///< n x n
};

} // namespace plantar::walking
