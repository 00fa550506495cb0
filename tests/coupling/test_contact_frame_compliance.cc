// rotate_compliance_to_contact_frames and rotate_compliance (coupling/contact_frame_compliance.h)
// against a dense reference T C T^T with T = blockdiag(F_k^T R), special cases
// with exact answers, no heap allocation (Eigen's malloc guard: this file and
// the library source are compiled with EIGEN_RUNTIME_NO_MALLOC, NDEBUG off),
// and the argument checks.
#include "coupling/contact_frame_compliance.h"

#include <Eigen/Geometry>
#include <gtest/gtest.h>

#include <cstdio>
#include <random>
#include <stdexcept>
#include <string>

namespace plantar::coupling {
namespace {

Eigen::Matrix3d random_rotation(std::mt19937& generator) {
  std::normal_distribution<double> normal;
  Eigen::Quaterniond q(normal(generator), normal(generator), normal(generator), normal(generator));
  return q.normalized().toRotationMatrix();
}

struct Fixture {
  explicit Fixture(int n_contacts, unsigned int seed) : generator(seed) {
    const int n = 3 * n_contacts;
    const Eigen::MatrixXd a = Eigen::MatrixXd::Random(n, n);
    compliance = 1e-6 * (a * a.transpose() + n * Eigen::MatrixXd::Identity(n, n)); // m/N, SPD
    rotation = random_rotation(generator);
    frames.resize(3, n);
    for (int k = 0; k < n_contacts; ++k)
      frames.middleCols<3>(3 * k) = random_rotation(generator);
    out.resize(n, n);
  }
  std::mt19937 generator;
  Eigen::MatrixXd compliance, frames, out;
  Eigen::Matrix3d rotation;
};

TEST(ContactFrameCompliance, MatchesDenseReference) {
  Fixture f(7, 3);
  rotate_compliance_to_contact_frames(f.compliance, f.rotation, f.frames, f.out);
  const int n = static_cast<int>(f.compliance.rows());
  Eigen::MatrixXd t = Eigen::MatrixXd::Zero(n, n);
  for (int k = 0; k < n / 3; ++k)
    t.block<3, 3>(3 * k, 3 * k) = f.frames.middleCols<3>(3 * k).transpose() * f.rotation;
  const Eigen::MatrixXd reference = t * f.compliance * t.transpose();
  const double scale = f.compliance.cwiseAbs().maxCoeff();
  const double error = (f.out - reference).cwiseAbs().maxCoeff() / scale;
  const double asymmetry = (f.out - f.out.transpose()).cwiseAbs().maxCoeff() / scale;
  // Same eigenvalues (an orthogonal similarity): compare the traces and norms.
  const double trace_error = std::abs(f.out.trace() - f.compliance.trace()) / f.compliance.trace();
  const double norm_error = std::abs(f.out.norm() - f.compliance.norm()) / f.compliance.norm();
  std::printf("\n7 contacts, random R and frames: max |out - T C T^T| / max|C| = %.2e, "
              "asymmetry %.2e, trace %.2e, Frobenius %.2e\n",
              error, asymmetry, trace_error, norm_error);
  EXPECT_LT(error, 1e-14);
  EXPECT_LT(asymmetry, 1e-14);
  EXPECT_LT(trace_error, 1e-14);
  EXPECT_LT(norm_error, 1e-14);
}

TEST(ContactFrameCompliance, ExactSpecialCases) {
  Fixture f(4, 5);
  // Frames equal to R: A_k = I, out = C.
  for (int k = 0; k < 4; ++k)
    f.frames.middleCols<3>(3 * k) = f.rotation;
  rotate_compliance_to_contact_frames(f.compliance, f.rotation, f.frames, f.out);
  const double identity_error = (f.out - f.compliance).cwiseAbs().maxCoeff();
  // Flat foot on the ground (the stepper's convention): R = I, n = +z, t1 = +x,
  // t2 = +y: rows (n, t1, t2) of a contact are rows (z, x, y) of the sole frame.
  Eigen::Matrix3d flat;
  flat.col(0) = Eigen::Vector3d::UnitZ();
  flat.col(1) = Eigen::Vector3d::UnitX();
  flat.col(2) = Eigen::Vector3d::UnitY();
  for (int k = 0; k < 4; ++k)
    f.frames.middleCols<3>(3 * k) = flat;
  rotate_compliance_to_contact_frames(f.compliance, Eigen::Matrix3d::Identity(), f.frames, f.out);
  const int axis[3] = {2, 0, 1};
  double permutation_error = 0;
  for (int i = 0; i < 12; ++i)
    for (int j = 0; j < 12; ++j)
      permutation_error = std::max(permutation_error,
                                   std::abs(f.out(i, j) - f.compliance(3 * (i / 3) + axis[i % 3],
                                                                       3 * (j / 3) + axis[j % 3])));
  std::printf("\nframes = R: max |out - C| = %.2e m/N; flat foot: max |out - P C P^T| = %.2e m/N\n",
              identity_error, permutation_error);
  EXPECT_LT(identity_error, 1e-15 * f.compliance.cwiseAbs().maxCoeff() * 10);
  EXPECT_EQ(permutation_error, 0.0);
}

TEST(ContactFrameCompliance, DoesNotAllocate) {
  Fixture f(20, 9);
  Eigen::internal::set_is_malloc_allowed(false);
  rotate_compliance_to_contact_frames(f.compliance, f.rotation, f.frames, f.out);
  Eigen::internal::set_is_malloc_allowed(true);
  EXPECT_TRUE(f.out.allFinite());
}

// rotate_compliance(R, C, out): blockwise R C(k, l) R^T, bitwise the identity-frames case.
TEST(ContactFrameCompliance, RotateComplianceIsTheIdentityFramesCase) {
  Fixture f(6, 13);
  const int n = static_cast<int>(f.compliance.rows());
  const Eigen::MatrixXd identity_frames = Eigen::Matrix3d::Identity().replicate(1, n / 3);
  Eigen::MatrixXd reference(n, n);
  rotate_compliance_to_contact_frames(f.compliance, f.rotation, identity_frames, reference);
  Eigen::internal::set_is_malloc_allowed(false);
  rotate_compliance(f.rotation, f.compliance, f.out);
  Eigen::internal::set_is_malloc_allowed(true);
  EXPECT_TRUE((f.out.array() == reference.array()).all()) << "not bitwise the same";
  double block_error = 0;
  for (int k = 0; k < n / 3; ++k)
    for (int l = 0; l < n / 3; ++l) {
      const Eigen::Matrix3d expected =
          f.rotation * f.compliance.block<3, 3>(3 * k, 3 * l) * f.rotation.transpose();
      block_error =
          std::max(block_error, (f.out.block<3, 3>(3 * k, 3 * l) - expected).cwiseAbs().maxCoeff());
    }
  std::printf("\nrotate_compliance: max |out - R C(k, l) R^T| = %.2e m/N\n", block_error);
  EXPECT_LT(block_error, 1e-15 * f.compliance.cwiseAbs().maxCoeff());
  Eigen::MatrixXd small(6, 6);
  EXPECT_THROW(rotate_compliance(f.rotation, f.compliance, small), std::invalid_argument);
  EXPECT_THROW(rotate_compliance(2.0 * f.rotation, f.compliance, f.out), std::invalid_argument);
  EXPECT_THROW(rotate_compliance(f.rotation, f.compliance.leftCols(6), f.out),
               std::invalid_argument);
}

// The guard is live in this build (otherwise DoesNotAllocate could not fail).
TEST(ContactFrameCompliance, MallocGuardIsLive) {
  EXPECT_DEATH(
      {
        Eigen::internal::set_is_malloc_allowed(false);
        Eigen::MatrixXd matrix(50, 50);
        matrix.setZero();
      },
      "");
}

TEST(ContactFrameCompliance, RejectsBadInput) {
  Fixture f(3, 11);
  Eigen::MatrixXd bad_frames = f.frames;
  bad_frames(0, 3) += 0.1; // contact 1 no longer orthonormal
  try {
    rotate_compliance_to_contact_frames(f.compliance, f.rotation, bad_frames, f.out);
    ADD_FAILURE() << "non-orthonormal frame accepted";
  } catch (const std::invalid_argument& error) {
    std::printf("\nmessage: %s\n", error.what());
    EXPECT_NE(std::string(error.what()).find("contact 1"), std::string::npos);
  }
  Eigen::MatrixXd small(6, 6);
  EXPECT_THROW(rotate_compliance_to_contact_frames(f.compliance, f.rotation, f.frames, small),
               std::invalid_argument);
  EXPECT_THROW(rotate_compliance_to_contact_frames(f.compliance, 2.0 * f.rotation, f.frames, f.out),
               std::invalid_argument);
  EXPECT_THROW(
      rotate_compliance_to_contact_frames(f.compliance, f.rotation, f.frames.leftCols(6), f.out),
      std::invalid_argument);
}

} // namespace
} // namespace plantar::coupling
