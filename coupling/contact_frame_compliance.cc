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

/// The checks shared by both functions: C square 3 n x 3 n, out of the same
/// size and not aliasing C, R orthonormal. Throws std::invalid_argument
/// starting with @p who (strings are built only when throwing: no allocation).
void check_arguments(const char* who, const Eigen::Ref<const Eigen::MatrixXd>& compliance,
                     const Eigen::Matrix3d& rotation,
                     const Eigen::Ref<const Eigen::MatrixXd>& out) {
  const Eigen::Index n_rows = compliance.rows();
  if (compliance.cols() != n_rows || n_rows % 3 != 0)
    throw std::invalid_argument(std::string(who) + ": compliance is " +
                                size_text(compliance.rows(), compliance.cols()) +
                                ", expected square 3 n x 3 n");
  if (out.rows() != n_rows || out.cols() != n_rows)
    throw std::invalid_argument(std::string(who) + ": out is " + size_text(out.rows(), out.cols()) +
                                ", expected " + size_text(n_rows, n_rows));
  if (out.data() == compliance.data())
    throw std::invalid_argument(std::string(who) + ": out aliases compliance");
  if (!is_orthonormal(rotation))
    throw std::invalid_argument(std::string(who) +
                                ": rotation R is not orthonormal (|R^T R - I| > 1e-9)");
}

/// out(k, l) = A_k C(k, l) A_l^T for every 3 x 3 block, A_k = frame(k) (3 x 3):
/// the one loop behind both public functions. Column pass then row pass,
/// fixed-size blocks only (no allocation).
template <class Frame>
void transform_blocks(const Eigen::Ref<const Eigen::MatrixXd>& compliance, const Frame& frame,
                      Eigen::Ref<Eigen::MatrixXd> out) {
  const Eigen::Index n_contacts = compliance.rows() / 3;
  for (Eigen::Index l = 0; l < n_contacts; ++l) {
    const Eigen::Matrix3d a_l = frame(l);
    for (Eigen::Index k = 0; k < n_contacts; ++k) {
      const Eigen::Matrix3d a_k = frame(k);
      const Eigen::Matrix3d block = compliance.block<3, 3>(3 * k, 3 * l);
      out.block<3, 3>(3 * k, 3 * l).noalias() = a_k * block * a_l.transpose();
    }
  }
}

} // namespace

void rotate_compliance_to_contact_frames(const Eigen::Ref<const Eigen::MatrixXd>& compliance,
                                         const Eigen::Matrix3d& rotation,
                                         const Eigen::Ref<const Eigen::MatrixXd>& frames,
                                         Eigen::Ref<Eigen::MatrixXd> out) {
  const char* who = "rotate_compliance_to_contact_frames";
  check_arguments(who, compliance, rotation, out);
  const Eigen::Index n_rows = compliance.rows();
  if (frames.rows() != 3 || frames.cols() != n_rows)
    throw std::invalid_argument(std::string(who) + ": frames is " +
                                size_text(frames.rows(), frames.cols()) + ", expected " +
                                size_text(3, n_rows));
  const Eigen::Index n_contacts = n_rows / 3;
  for (Eigen::Index k = 0; k < n_contacts; ++k)
    if (!is_orthonormal(frames.middleCols<3>(3 * k)))
      throw std::invalid_argument(std::string(who) + ": frame of contact " + std::to_string(k) +
                                  " (columns n, t1, t2) is not orthonormal (tolerance 1e-9)");
  // A_k = F_k^T R.
  transform_blocks(
      compliance,
      [&](Eigen::Index k) -> Eigen::Matrix3d {
        return frames.middleCols<3>(3 * k).transpose() * rotation;
      },
      out);
}

void rotate_compliance(const Eigen::Matrix3d& rotation,
                       const Eigen::Ref<const Eigen::MatrixXd>& compliance,
                       Eigen::Ref<Eigen::MatrixXd> out) {
  check_arguments("rotate_compliance", compliance, rotation, out);
  // A_k = R for every node (F_k = I: I^T R equals R entry by entry, exactly).
  transform_blocks(
      compliance, [&](Eigen::Index) -> const Eigen::Matrix3d& { return rotation; }, out);
}

} // namespace plantar::coupling
