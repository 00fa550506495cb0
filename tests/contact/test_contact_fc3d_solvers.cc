// Every shared third-party problem (../shared/data/fc3d) solved to 1e-8 by Siconos's error
// measure with Plantar's automatic choice and semismooth Newton: the error computed by Siconos
// itself (fc3d_compute_error) and by our own implementation (same number). Where W is positive
// definite (smallest eigenvalue of its symmetric part > 1e-8 of the largest) the solution is
// compared with Siconos's semismooth Newton (NSN_AC) solution. Newton alone, from zero, solves
// all of them, KaplasTower included (where Siconos's NSN_AC does not).
#include "tests/contact/fc3d_files.h"
#include "tests/contact/fc3d_solve.h"
#include "tests/contact/siconos_format.h"
#include "tests/contact/siconos_oracle.h"

#include <Eigen/Eigenvalues>
#include <cctype>
#include <cstdio>
#include <gtest/gtest.h>

namespace plantar::contact::testing {
namespace {

constexpr double kTolerance = 1e-8;

class Fc3dSolvers : public ::testing::TestWithParam<std::string> {};

TEST_P(Fc3dSolvers, AutoAndNewtonReachTheToleranceOfSiconosMeasure) {
  const std::string path = fc3d_data_dir() + "/" + GetParam() + ".dat";
  const SiconosProblem source = read_siconos_problem(path);
  const SiconosOracle oracle(path);
  const Eigen::MatrixXd w = source.dense_w();
  const auto ours = [&](const Eigen::VectorXd& r) { return fc3d_error(w, source.q, source.mu, r); };
  const Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eigen(0.5 * (w + w.transpose()),
                                                             Eigen::EigenvaluesOnly);
  const bool unique = eigen.eigenvalues().minCoeff() > 1e-8 * eigen.eigenvalues().maxCoeff();
  // Siconos's semismooth Newton, tighter, as the reference solution where it is unique.
  SiconosOracle::Run reference;
  if (unique)
    reference = oracle.solve(504 /* SICONOS_FRICTION_3D_NSN_AC */, 1e-12, 5000);
  for (const ContactSolverType type : {ContactSolverType::automatic, ContactSolverType::newton}) {
    SCOPED_TRACE(to_string(type));
    const Fc3dSolve solve = solve_to_tolerance(source, type, kTolerance, 10000, ours);
    const double siconos_error = oracle.error(solve.r);
    const double difference =
        unique ? (solve.r - reference.r).norm() / std::max(reference.r.norm(), 1e-300) : -1.0;
    std::printf("%-30s %-7s %6d it %8.4f s error %.2e (Siconos %.2e) finished by %s (%s@%d, %s)"
                " unique %d |r - r_NSN|/|r_NSN| %.1e (NSN_AC error %.1e)\n",
                GetParam().c_str(), to_string(type), solve.iterations, solve.seconds, solve.error,
                siconos_error, to_string(solve.last.finished_by),
                to_string(solve.last.switch_reason), solve.last.switch_iteration,
                to_string(solve.last.newton_linear_solve), unique, difference, reference.error);
    EXPECT_LE(siconos_error, kTolerance);
    EXPECT_LE(solve.error, kTolerance);
    EXPECT_NEAR(solve.error, siconos_error, 1e-10 * siconos_error + 1e-15);
    if (unique && reference.info == 0) {
      EXPECT_LT(difference, 1e-6);
    }
  }
}

std::vector<std::string> fc3d_names() {
  std::vector<std::string> names;
  for (const std::string& path : fc3d_files()) {
    std::string name = path.substr(path.find_last_of('/') + 1);
    names.push_back(name.substr(0, name.rfind(".dat")));
  }
  return names;
}

INSTANTIATE_TEST_SUITE_P(Shared, Fc3dSolvers, ::testing::ValuesIn(fc3d_names()),
                         [](const ::testing::TestParamInfo<std::string>& info) {
                           std::string name = info.param;
                           for (char& c : name)
                             if (!std::isalnum(static_cast<unsigned char>(c)))
                               c = '_';
                           return name;
                         });

} // namespace
} // namespace plantar::contact::testing
