#pragma once
// A height grid from a CSV file, interpolated bilinearly.
// File: one grid row per line, heights (m) separated by commas; row r is y = y0 + r d, column c
// is x = x0 + c d (d the spacing); lines that are empty or start with '#' are skipped; at least
// 2 rows of at least 2 values, every row the same length, every value finite.
// Inside cell [x_c, x_c + d] x [y_r, y_r + d], with u, v in [0, 1]:
//   h = (1-u)(1-v) h00 + u (1-v) h10 + (1-u) v h01 + u v h11   (exact for planes),
//   h_x = ((1-v)(h10 - h00) + v (h11 - h01)) / d,  h_y = ((1-u)(h01 - h00) + u (h11 - h10)) / d;
// the gradient (and so the frame) jumps across cell edges. Outside the grid the point is
// clamped onto its border: the border's height, gradient zero.

#include "contact/terrain.h"

#include <string>
#include <vector>

namespace plantar::contact {

class GridTerrain final : public Terrain {
public:
  /// Reads @p path. @p spacing d (m, > 0), @p origin (x0, y0) of the first value (m, finite),
  /// @p level z0 added to every height (m, finite). Throws std::invalid_argument naming the
  /// file, and the line and column of a bad value or row.
  GridTerrain(const std::string& path, double spacing, const Eigen::Vector2d& origin, double level);
  /// From values in memory (@p heights (rows = y, columns = x), m): for tests.
  GridTerrain(const Eigen::MatrixXd& heights, double spacing, const Eigen::Vector2d& origin,
              double level);
  double height(double x, double y) const override;
  Eigen::Vector2d gradient(double x, double y) const override;
  int n_rows() const { return static_cast<int>(heights_.rows()); }
  int n_columns() const { return static_cast<int>(heights_.cols()); }

private:
  void check(const std::string& source) const;
  bool locate(double x, double y, int& c, int& r, double& u, double& v) const;

  Eigen::MatrixXd heights_; // (rows = y, columns = x) + level
  double spacing_;
  Eigen::Vector2d origin_;
};

} // namespace plantar::contact
