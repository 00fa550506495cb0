#include "tests/contact/boussinesq_compliance.h"

#include <cmath>

namespace plantar::contact::test {

Eigen::MatrixXd square_grid(int n_side, double spacing) {
  return rectangular_grid(n_side, n_side, spacing);
}

Eigen::MatrixXd rectangular_grid(int n_x, int n_y, double spacing) {
  Eigen::MatrixXd positions(n_x * n_y, 2);
  const double offset_x = 0.5 * (n_x - 1) * spacing, offset_y = 0.5 * (n_y - 1) * spacing;
  for (int i = 0; i < n_x; ++i)
    for (int j = 0; j < n_y; ++j)
      positions.row(i * n_y + j) << i * spacing - offset_x, j * spacing - offset_y;
  return positions;
}

Eigen::MatrixXd boussinesq_compliance(const Eigen::MatrixXd& positions, double spacing,
                                      double young, double poisson) {
  const double pi = 3.14159265358979323846;
  const int n = static_cast<int>(positions.rows());
  const double nu = poisson;
  const double self = 4.0 * std::log(1.0 + std::sqrt(2.0)) / (pi * young * spacing);
  Eigen::MatrixXd c = Eigen::MatrixXd::Zero(3 * n, 3 * n);
  for (int i = 0; i < n; ++i) {
    c(3 * i, 3 * i) = self * (1.0 - nu * nu);
    c(3 * i + 1, 3 * i + 1) = self * (1.0 + nu) * (1.0 - 0.5 * nu);
    c(3 * i + 2, 3 * i + 2) = self * (1.0 + nu) * (1.0 - 0.5 * nu);
    for (int j = 0; j < n; ++j) {
      if (i == j)
        continue;
      const double dx = positions(i, 0) - positions(j, 0);
      const double dy = positions(i, 1) - positions(j, 1);
      const double r = std::hypot(dx, dy);
      const double k = (1.0 + nu) / (pi * young * r);
      c(3 * i, 3 * j) = (1.0 - nu * nu) / (pi * young * r);
      c(3 * i + 1, 3 * j + 1) = k * ((1.0 - nu) + nu * dx * dx / (r * r));
      c(3 * i + 2, 3 * j + 2) = k * ((1.0 - nu) + nu * dy * dy / (r * r));
      c(3 * i + 1, 3 * j + 2) = k * nu * dx * dy / (r * r);
      c(3 * i + 2, 3 * j + 1) = k * nu * dx * dy / (r * r);
    }
  }
  return c;
}

} // namespace plantar::contact::test
