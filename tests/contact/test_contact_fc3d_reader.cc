// The Siconos-format reader (siconos_format.h) against Siconos's own reader, and the
// independent error measure against fc3d_compute_error, on every shared problem.
#include "contact/siconos_writer.h"
#include "tests/contact/fc3d_files.h"
#include "tests/contact/siconos_format.h"
#include "tests/contact/siconos_oracle.h"
#include "tests/contact/sticking_problem.h"

#include <cstdio>
#include <filesystem>
#include <fstream>
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

// The writer (contact/siconos_writer.h) against Siconos's own reader: a problem with a rigid
// factor, two rotated compliant patches and normal biases is written, read back by Siconos
// bit for bit as assembled (W dense, q = v_free + b e_n, mu), and the fixture's known sticking
// solution is a solution of the written problem by Siconos's error measure.
TEST(SiconosWriter, SiconosReadsTheProblemAsAssembled) {
  const auto fixture = plantar::contact::test::sticking_problem(6, 8, 1.0, 0.5, -1, 17);
  const ContactProblem& problem = fixture.problem;
  const std::filesystem::path path =
      std::filesystem::temp_directory_path() / "plantar_siconos_writer_test.dat";
  {
    std::ofstream out(path);
    write_siconos_problem(problem, out);
  }
  const SiconosOracle theirs(path.string());
  Eigen::MatrixXd w;
  problem.assemble_delassus(w);
  Eigen::VectorXd q = problem.free_velocity.head(3 * problem.n_contacts);
  for (int k = 0; k < problem.n_contacts; ++k)
    q[3 * k] += problem.normal_bias[k];
  ASSERT_EQ(theirs.n_contacts(), problem.n_contacts);
  EXPECT_EQ((theirs.w().array() != w.array()).count(), 0);
  EXPECT_EQ((theirs.q().array() != q.array()).count(), 0);
  EXPECT_EQ((theirs.mu().array() != problem.friction.head(problem.n_contacts).array()).count(), 0);
  const double error = theirs.error(fixture.solution);
  std::printf("written: %d contacts, rigid rank %d, %zu patches; Siconos's error at the known "
              "solution %.2e\n",
              problem.n_contacts, problem.rigid_rank(), problem.patches.size(), error);
  EXPECT_LT(error, 1e-12);
  EXPECT_EQ(read_siconos_problem(path.string()).n_contacts, problem.n_contacts);
  std::filesystem::remove(path);
}

// A start written with write_warm_start reads back bit for bit; a start of another problem's
// size is refused with the file and both sizes named.
TEST(SiconosWriter, WarmStartReadsBackBitForBit) {
  const auto fixture = plantar::contact::test::sticking_problem(6, 8, 1.0, 0.5, -1, 17);
  const int n = fixture.problem.n_contacts;
  Eigen::VectorXd start = fixture.solution.head(3 * n);
  start[1] = -1.0 / 3.0; // digits a shorter format would lose
  start[2] = 1e-300;
  const std::filesystem::path path =
      std::filesystem::temp_directory_path() / "plantar_warm_start_test.txt";
  {
    std::ofstream out(path);
    write_warm_start(n, start, out);
  }
  const Eigen::VectorXd read = read_warm_start(path.string(), n);
  ASSERT_EQ(read.size(), 3 * n);
  EXPECT_EQ((read.array() != start.array()).count(), 0);
  try {
    read_warm_start(path.string(), n + 1);
    ADD_FAILURE() << "a start of " << n << " contacts was read for " << n + 1;
  } catch (const std::runtime_error& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find(path.string()), std::string::npos) << what;
    EXPECT_NE(what.find("the problem's " + std::to_string(n + 1) + " contacts (read " +
                        std::to_string(n) + ")"),
              std::string::npos)
        << what;
  }
  std::filesystem::remove(path);
}

TEST(Fc3dReader, MalformedFileGivesClearError) {
  EXPECT_THROW(read_siconos_problem("/nonexistent.dat"), std::runtime_error);
}

} // namespace
} // namespace plantar::contact::testing
