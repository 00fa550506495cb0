// The Siconos-format reader (siconos_format.h) against Siconos's own reader, and the
// independent error measure against fc3d_compute_error, on every shared problem.
#include "tests/contact/fc3d_files.h"
#include "tests/contact/siconos_format.h"
#include "tests/contact/siconos_oracle.h"

#include <gtest/gtest.h>

namespace plantar::contact::testing {
namespace {

TEST(Fc3dReader, SameBitsAsSiconosOnEveryFile) {
  const auto files = fc3d_files();
  EXPECT_EQ(files.size(), 17u);
  for (const std::string& path : files) {
    SCOPED_TRACE(path);
    const SiconosProblem ours = read_siconos_problem(path);
    const SiconosOracle theirs(path);
    ASSERT_EQ(ours.n_contacts, theirs.n_contacts());
    const Eigen::MatrixXd w = ours.dense_w(), w_siconos = theirs.w();
    ASSERT_EQ(w.rows(), w_siconos.rows());
    // Bitwise: == on doubles (no NaN in these files).
    EXPECT_EQ((w.array() != w_siconos.array()).count(), 0);
    EXPECT_EQ((ours.q.array() != theirs.q().array()).count(), 0);
    EXPECT_EQ((ours.mu.array() != theirs.mu().array()).count(), 0);
  }
}

TEST(Fc3dReader, ErrorMeasureMatchesSiconos) {
  // At a random point and at Siconos's own NSGS iterate after three sweeps, our fc3d_error and
  // Siconos's fc3d_compute_error agree to round-off.
  for (const std::string& path : fc3d_files()) {
    SCOPED_TRACE(path);
    const SiconosProblem ours = read_siconos_problem(path);
    const SiconosOracle theirs(path);
    const Eigen::MatrixXd w = ours.dense_w();
    Eigen::VectorXd r = Eigen::VectorXd::Random(w.rows()) * (ours.q.norm() / (1.0 + w.norm()));
    const double a = fc3d_error(w, ours.q, ours.mu, r), b = theirs.error(r);
    EXPECT_NEAR(a, b, 1e-12 * b + 1e-300);
    const auto run = theirs.solve(500 /* SICONOS_FRICTION_3D_NSGS */, 1e-14, 3);
    const double c = fc3d_error(w, ours.q, ours.mu, run.r), d = theirs.error(run.r);
    EXPECT_NEAR(c, d, 1e-10 * d + 1e-15); // round-off of W r + q: ~1e-16
  }
}

TEST(Fc3dReader, MalformedFileGivesClearError) {
  EXPECT_THROW(read_siconos_problem("/nonexistent.dat"), std::runtime_error);
}

} // namespace
} // namespace plantar::contact::testing
