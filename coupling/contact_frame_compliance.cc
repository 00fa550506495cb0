#include "coupling/contact_frame_compliance.h"

#include <cmath>
#include <stdexcept>
#include <string>

namespace plantar::coupling {
namespace {

constexpr double orthonormality_tolerance = 1e-9;

bool is_orthonormal(const Eigen::Matrix3d& matrix) {
  return ((matrix.transpose() * matrix - Eigen::Matrix3d::Identity()).cwiseAbs().maxCoeff() <=
          orthonormality_tolerance) &&
         matrix.allFinite();
}

std::string size_text(Eigen::Index rows, Eigen::Index cols) {
  return std::to_string(rows) + " x " + std::to_string(cols);
}

} // namespace

void rotate_compliance_to_contact_frames(const Eigen::Ref<const Eigen::MatrixXd>& compliance,
                                         const Eigen::Matrix3d& rotation,
                                         const Eigen::Ref<const Eigen::MatrixXd>& frames,
                                         Eigen::Ref<Eigen::MatrixXd> out) {
  const Eigen::Index n_rows = compliance.rows();
  if (compliance.cols() != n_rows || n_rows % 3 != 0)
    throw std::invalid_argument("rotate_compliance_to_contact_frames: compliance is " +
                                size_text(compliance.rows(), compliance.cols()) +
                                ", expected square 3 n x 3 n");
  if (frames.rows() != 3 || frames.cols() != n_rows)
    throw std::invalid_argument("rotate_compliance_to_contact_frames: frames is " +
                                size_text(frames.rows(), frames.cols()) + ", expected " +
                                size_text(3, n_rows));
  if (out.rows() != n_rows || out.cols() != n_rows)
    throw std::invalid_argument("rotate_compliance_to_contact_frames: out is " +
                                size_text(out.rows(), out.cols()) + ", expected " +
                                size_text(n_rows, n_rows));
  if (out.data() == compliance.data())
    throw std::invalid_argument("rotate_compliance_to_contact_frames: out aliases compliance");
  if (!is_orthonormal(rotation))
    throw std::invalid_argument("rotate_compliance_to_contact_frames: rotation R is not "
                                "orthonormal (|R^T R - I| > 1e-9)");
  const Eigen::Index n_contacts = n_rows / 3;
  for (Eigen::Index k = 0; k < n_contacts; ++k)
    if (!is_orthonormal(frames.middleCols<3>(3 * k)))
      throw std::invalid_argument("rotate_compliance_to_contact_frames: frame of contact " +
                                  std::to_string(k) +
                                  " (columns n, t1, t2) is not orthonormal (tolerance 1e-9)");

  // Column pass then row pass, fixed-size 3 x 3 blocks only (no allocation).
  for (Eigen::Index l = 0; l < n_contacts; ++l) {
    const Eigen::Matrix3d a_l = frames.middleCols<3>(3 * l).transpose() * rotation;
    for (Eigen::Index k = 0; k < n_contacts; ++k) {
      const Eigen::Matrix3d a_k = frames.middleCols<3>(3 * k).transpose() * rotation;
      const Eigen::Matrix3d block = compliance.block<3, 3>(3 * k, 3 * l);
      out.block<3, 3>(3 * k, 3 * l).noalias() = a_k * block * a_l.transpose();
    }
  }
}

} // namespace plantar::coupling
