#include "contact/symmetry.h"

#include <algorithm>
#include <cmath>
#include <sstream>
#include <stdexcept>

namespace plantar::contact {

double relative_asymmetry(const Eigen::Ref<const Eigen::MatrixXd>& a) {
  double asymmetry = 0, largest = 0;
  for (Eigen::Index j = 0; j < a.cols(); ++j) {
    for (Eigen::Index i = 0; i < a.rows(); ++i) {
      largest = std::max(largest, std::abs(a(i, j)));
      if (i < j)
        asymmetry = std::max(asymmetry, std::abs(a(i, j) - a(j, i)));
    }
  }
  return largest > 0 ? asymmetry / largest : 0.0;
}

void check_symmetric(const Eigen::Ref<const Eigen::MatrixXd>& a, const char* where,
                     const char* what, double tolerance) {
  const double asymmetry = relative_asymmetry(a);
  if (asymmetry > tolerance) {
    std::ostringstream msg;
    msg << where << ": " << what << " is not symmetric (relative asymmetry " << asymmetry << " > "
        << tolerance << ")";
    throw std::invalid_argument(msg.str());
  }
}

} // namespace plantar::contact
