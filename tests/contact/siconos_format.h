#pragma once
// Reader of Siconos numerics' text format of a FrictionContactProblem (a reduced 3D frictional
// contact problem u = W r + q, r in the Coulomb cones, De Saxce's u + mu ||u_T|| e_N in their
// duals), written from the format as Siconos writes it:
//   dimension (3), number of contacts n,
//   the NumericsMatrix W: storage type (0 dense, 1 sparse block), size0, size1, then
//     dense:        size0 size1 again, size0 * size1 values, column-major;
//     sparse block: number of blocks, block rows, block columns, the cumulative row and column
//                   block sizes, filled1 filled2, the block-row pointers (filled1), the block
//                   column indices (filled2), then per block its number and its values
//                   (column-major within the block);
//   q (size0 values), mu (n values).
// Contacts are ordered (normal, tangent, tangent). Used by the tests and bench/contact/fc3d_bench.

#include "contact/contact_problem.h"

#include <Eigen/Core>
#include <Eigen/SparseCore>
#include <string>

namespace plantar::contact::testing {

struct SiconosProblem {
  int dimension = 3;
  int n_contacts = 0;
  bool sparse_block = false;          ///< W was stored as a sparse-block matrix
  Eigen::SparseMatrix<double> sparse; ///< W when sparse_block (3n x 3n)
  Eigen::MatrixXd dense;              ///< W when stored dense (3n x 3n)
  Eigen::VectorXd q;                  ///< 3n, m/s
  Eigen::VectorXd mu;                 ///< n
  /// W as a dense matrix (either storage).
  Eigen::MatrixXd dense_w() const;
};

/// Reads @p path. Throws std::runtime_error naming the file and what was expected on a short or
/// malformed file, a dimension other than 3 or an unsupported matrix storage.
SiconosProblem read_siconos_problem(const std::string& path);

/// Reads a start for the solve of an @p n_contacts problem, as contact/siconos_writer.h
/// write_warm_start writes it ("3", n, 3n impulses). Throws std::runtime_error naming the file
/// when it is short or malformed or its n differs from @p n_contacts.
Eigen::VectorXd read_warm_start(const std::string& path, int n_contacts);

/// Poses @p source as a ContactProblem (rigid rank 0, no patches, zero normal bias,
/// W_gen = W kept as stored: dense or sparse). Returns W's relative asymmetry; throws when it
/// exceeds @p asymmetry_limit (GeneralDelassus).
double pose_problem(const SiconosProblem& source, ContactProblem& problem,
                    AsymmetryPolicy policy = AsymmetryPolicy::keep, double asymmetry_limit = 1e-3);

/// Siconos's error measure of a FrictionContactProblem (fc3d_compute_error of Siconos numerics
/// 4.4 as installed), written here independently: u = W r + q,
///   error = sqrt(sum_k || r_k - P_K(r_k - (u_k + mu_k ||u_k,T|| e_N)) ||^2)
///           / max(||q||, ||u||, ||r||)
/// (not divided when that is <= DBL_EPSILON). The normalisation was found by testing the
/// installed library (its later sources divide by ||q|| only): see docs/contact_solvers.md.
/// @p w the problem's W (dense).
double fc3d_error(const Eigen::MatrixXd& w, const Eigen::VectorXd& q, const Eigen::VectorXd& mu,
                  const Eigen::VectorXd& r);

} // namespace plantar::contact::testing
