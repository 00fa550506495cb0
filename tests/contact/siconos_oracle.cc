#include "tests/contact/siconos_oracle.h"

#include <chrono>
#include <stdexcept>

#include <FrictionContactProblem.h>
#include <Friction_cst.h>
#include <NonSmoothDrivers.h>
#include <NumericsMatrix.h>
#include <SolverOptions.h>
#include <fc3d_compute_error.h>

namespace plantar::contact::testing {

struct SiconosOracle::Problem {
  FrictionContactProblem* fc = nullptr;
};

SiconosOracle::SiconosOracle(const std::string& path) : problem_(std::make_unique<Problem>()) {
  problem_->fc = frictionContact_new_from_filename(path.c_str());
  if (problem_->fc == nullptr || problem_->fc->M == nullptr)
    throw std::runtime_error("SiconosOracle: Siconos could not read " + path);
}

SiconosOracle::~SiconosOracle() {
  if (problem_->fc != nullptr)
    frictionContactProblem_free(problem_->fc);
}

int SiconosOracle::n_contacts() const {
  return problem_->fc->numberOfContacts;
}

Eigen::MatrixXd SiconosOracle::w() const {
  NumericsMatrix* m = problem_->fc->M;
  Eigen::MatrixXd out(m->size0, m->size1);
  for (int j = 0; j < m->size1; ++j)
    for (int i = 0; i < m->size0; ++i)
      out(i, j) = NM_get_value(m, i, j);
  return out;
}

Eigen::VectorXd SiconosOracle::q() const {
  return Eigen::Map<const Eigen::VectorXd>(problem_->fc->q, problem_->fc->M->size0);
}

Eigen::VectorXd SiconosOracle::mu() const {
  return Eigen::Map<const Eigen::VectorXd>(problem_->fc->mu, n_contacts());
}

double SiconosOracle::error(const Eigen::VectorXd& r) const {
  Eigen::VectorXd z = r, u(r.size());
  double error = 0.0;
  fc3d_compute_error(problem_->fc, z.data(), u.data(), 0.0, nullptr, q().norm(), &error);
  return error;
}

SiconosOracle::Run SiconosOracle::solve(int solver_id, double tolerance, int max_iterations,
                                        const Eigen::VectorXd* start) const {
  SolverOptions* options = solver_options_create(solver_id);
  if (options == nullptr)
    throw std::runtime_error("SiconosOracle: unknown solver id " + std::to_string(solver_id));
  options->iparam[SICONOS_IPARAM_MAX_ITER] = max_iterations;
  options->dparam[SICONOS_DPARAM_TOL] = tolerance;
  Run run;
  run.r = Eigen::VectorXd::Zero(problem_->fc->M->size0);
  if (start != nullptr) {
    if (start->size() != run.r.size())
      throw std::runtime_error("SiconosOracle::solve: a start of size " +
                               std::to_string(start->size()) + " for " +
                               std::to_string(run.r.size()) + " unknowns");
    run.r = *start;
  }
  run.u = Eigen::VectorXd::Zero(problem_->fc->M->size0);
  const auto begin = std::chrono::steady_clock::now();
  run.info = fc3d_driver(problem_->fc, run.r.data(), run.u.data(), options);
  run.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - begin).count();
  run.iterations = options->iparam[SICONOS_IPARAM_ITER_DONE];
  run.error = options->dparam[SICONOS_DPARAM_RESIDU];
  solver_options_delete(options);
  return run;
}

} // namespace plantar::contact::testing
