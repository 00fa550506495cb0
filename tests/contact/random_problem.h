#pragma once
// Test/benchmark fixture: random well-posed contact problems.
#include "contact/contact_problem.h"

#include <random>

namespace plantar::contact::test {

/// n contacts, rigid factor with m random columns, and (if n_patch > 0) one
/// random SPD patch block on contacts [0, n_patch) (C/dt^2 ~ patch_scale).
/// Free velocities random in [-1, 1] m/s with a downward bias, mu in [0.2, 1].
inline ContactProblem random_problem(int n, int m, int n_patch, double patch_scale, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> unit(-1.0, 1.0);
  ContactProblem problem;
  problem.resize(n, m);
  problem.n_contacts = n;
  for (int i = 0; i < 3 * n; ++i)
    for (int j = 0; j < m; ++j)
      problem.rigid_factor(i, j) = unit(rng);
  for (int i = 0; i < 3 * n; ++i)
    problem.free_velocity[i] = unit(rng) - (i % 3 == 0 ? 0.5 : 0.0);
  for (int k = 0; k < n; ++k) {
    problem.friction[k] = 0.6 + 0.4 * unit(rng);
    problem.normal_bias[k] = 0.0;
  }
  if (n_patch > 0) {
    CompliantPatch patch;
    patch.first_contact = 0;
    patch.n_contacts = n_patch;
    Eigen::MatrixXd a(3 * n_patch, 3 * n_patch);
    for (int i = 0; i < a.rows(); ++i)
      for (int j = 0; j < a.cols(); ++j)
        a(i, j) = unit(rng);
    patch.compliance_over_dt =
        patch_scale *
        (a * a.transpose() / a.rows() + 0.1 * Eigen::MatrixXd::Identity(3 * n_patch, 3 * n_patch));
    problem.patches.push_back(patch);
  }
  return problem;
}

} // namespace plantar::contact::test
