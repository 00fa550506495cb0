#pragma once
// Siconos numerics 4.4 as a test-only oracle (tests/contact and bench/contact link it, never
// plantar_contact): its own reader of a FrictionContactProblem file, its error measure
// (fc3d_compute_error) and its solvers (fc3d_driver).

#include <Eigen/Core>
#include <memory>
#include <string>

namespace plantar::contact::testing {

class SiconosOracle {
public:
  /// Reads @p path with frictionContact_new_from_filename. Throws std::runtime_error on failure.
  explicit SiconosOracle(const std::string& path);
  ~SiconosOracle();
  SiconosOracle(const SiconosOracle&) = delete;
  SiconosOracle& operator=(const SiconosOracle&) = delete;

  int n_contacts() const;
  /// W as Siconos holds it, entry by entry (NM_get_value), dense 3n x 3n.
  Eigen::MatrixXd w() const;
  Eigen::VectorXd q() const;
  Eigen::VectorXd mu() const;
  /// Siconos's error of reactions @p r (3n): fc3d_compute_error with norm ||q||.
  double error(const Eigen::VectorXd& r) const;

  struct Run {
    int info = -1;        ///< 0: converged
    int iterations = 0;   ///< iparam[SICONOS_IPARAM_ITER_DONE]
    double error = 0.0;   ///< dparam[SICONOS_DPARAM_RESIDU]
    double seconds = 0.0; ///< wall time of fc3d_driver
    Eigen::VectorXd r, u; ///< reactions and velocities
  };
  /// Solves with @p solver_id (e.g. SICONOS_FRICTION_3D_NSGS = 500,
  /// SICONOS_FRICTION_3D_NSN_AC = 504), tolerance and iteration cap, from @p start (3n
  /// reactions, fc3d_driver's initial guess) or, when null, from zero.
  Run solve(int solver_id, double tolerance, int max_iterations,
            const Eigen::VectorXd* start = nullptr) const;

private:
  struct Problem;
  std::unique_ptr<Problem> problem_;
};

} // namespace plantar::contact::testing
