#pragma once
// Test fixture: a contact problem of two soles fixed to two rigid bodies, with the rigid rows
// in the factored form of PatchLever::lever (G_j = (I (x) R_j) Lambda_j T_j) and a known
// solution in which every contact sticks.
#include "contact/contact_problem.h"

#include <Eigen/Geometry>
#include <Eigen/QR>
#include <cmath>
#include <random>
#include <vector>

namespace plantar::contact::test {

struct StickingProblem {
  ContactProblem problem;
  Eigen::VectorXd solution; ///< p* (3 n), contact frames
};

/// Two patches of @p n_nodes nodes (a 0.24 x 0.12 m grid-like sole 0.1 m below the body
/// origin, jittered), random SPD C/dt^2 (about @p patch_scale), random rotations R_j and maps
/// T_j (6 x m), normal bias b_k in [0, 0.01] m/s. p* has p_n in [0.5, 1.5] N s and
/// |p_t| = @p friction_use mu p_n on every contact; contact @p outside_contact (if >= 0) has
/// |p_t| = 1.5 mu p_n instead (no sticking solution: the direct solve must refuse it).
/// v_free = -W p* - b e_n, so p* solves the sticking system W p = -(v_free + b e_n).
/// With @p condition > 0, each C/dt^2 is instead patch_scale Q diag(lambda) Q^T, Q orthogonal
/// (random), lambda from 1 down to 1/condition evenly in log (condition number @p condition).
inline StickingProblem sticking_problem(int n_nodes, int m, double patch_scale, double friction_use,
                                        int outside_contact, unsigned seed,
                                        double condition = 0.0) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> unit(-1.0, 1.0);
  const int n = 2 * n_nodes;
  StickingProblem out;
  ContactProblem& problem = out.problem;
  problem.resize(n, m);
  problem.n_contacts = n;
  for (int j = 0; j < 2; ++j) {
    Eigen::Matrix3Xd nodes(3, n_nodes);
    for (int k = 0; k < n_nodes; ++k)
      nodes.col(k) = Eigen::Vector3d(0.12 * unit(rng), 0.06 * unit(rng), -0.1);
    CompliantPatch patch;
    patch.first_contact = j * n_nodes;
    patch.n_contacts = n_nodes;
    Eigen::MatrixXd a(3 * n_nodes, 3 * n_nodes);
    for (int r = 0; r < a.rows(); ++r)
      for (int c = 0; c < a.cols(); ++c)
        a(r, c) = unit(rng);
    if (condition > 0.0) {
      const Eigen::MatrixXd q = a.householderQr().householderQ();
      Eigen::VectorXd lambda(a.rows());
      for (Eigen::Index i = 0; i < a.rows(); ++i)
        lambda[i] = std::pow(condition, -double(i) / double(a.rows() - 1));
      patch.compliance_over_dt = patch_scale * q * lambda.asDiagonal() * q.transpose();
      patch.compliance_over_dt =
          (0.5 * (patch.compliance_over_dt + patch.compliance_over_dt.transpose())).eval();
    } else {
      patch.compliance_over_dt =
          patch_scale *
          (a * a.transpose() / a.rows() + 0.05 * Eigen::MatrixXd::Identity(a.rows(), a.rows()));
    }
    patch.rotation =
        Eigen::AngleAxisd(0.4 * unit(rng), Eigen::Vector3d(unit(rng), unit(rng), 1).normalized())
            .toRotationMatrix();
    PatchLever structure;
    structure.lever_map.resize(6, m);
    for (int r = 0; r < 6; ++r)
      for (int c = 0; c < m; ++c)
        structure.lever_map(r, c) = 0.3 * unit(rng);
    structure.lever_map_valid = true;
    const Eigen::MatrixXd lever = rigid_lever(nodes);
    set_sticking_structure(structure, lever);
    const Eigen::MatrixXd rows = lever * structure.lever_map; // patch frame
    for (int k = 0; k < n_nodes; ++k)
      problem.rigid_factor.middleRows<3>(3 * (patch.first_contact + k)) =
          patch.rotation * rows.middleRows<3>(3 * k);
    problem.patches.push_back(patch);
    problem.patch_levers.push_back(structure);
  }
  out.solution.resize(3 * n);
  for (int k = 0; k < n; ++k) {
    problem.friction[k] = 0.8 + 0.3 * unit(rng);
    problem.normal_bias[k] = 0.005 * (1.0 + unit(rng));
    const double p_n = 1.0 + 0.5 * unit(rng);
    const double angle = 3.14159 * unit(rng);
    const double t = (k == outside_contact ? 1.5 : friction_use) * problem.friction[k] * p_n;
    out.solution.segment<3>(3 * k) = Eigen::Vector3d(p_n, t * std::cos(angle), t * std::sin(angle));
  }
  Eigen::MatrixXd w;
  problem.assemble_delassus(w);
  problem.free_velocity.head(3 * n) = -w * out.solution;
  for (int k = 0; k < n; ++k)
    problem.free_velocity[3 * k] -= problem.normal_bias[k];
  return out;
}

/// Makes the contacts with separated[k] != 0 separated in the solution (p*_k = 0, the De
/// Saxce velocity v + (b + mu |v_t|) e_n = (0.02 + mu |v_t|, v_t) with a random v_t) and the
/// others sticking with the impulses of fixture.solution: sets fixture.solution and v_free.
inline void separate_contacts(StickingProblem& fixture, const std::vector<char>& separated,
                              unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> unit(-1.0, 1.0);
  ContactProblem& problem = fixture.problem;
  const int n = problem.n_contacts;
  for (int k = 0; k < n; ++k)
    if (separated[k])
      fixture.solution.segment<3>(3 * k).setZero();
  Eigen::MatrixXd w;
  problem.assemble_delassus(w);
  problem.free_velocity.head(3 * n) = -w * fixture.solution;
  for (int k = 0; k < n; ++k) {
    problem.free_velocity[3 * k] -= problem.normal_bias[k];
    if (separated[k])
      problem.free_velocity.segment<3>(3 * k) +=
          Eigen::Vector3d(0.02, 0.05 * unit(rng), 0.05 * unit(rng));
  }
}

} // namespace plantar::contact::test
