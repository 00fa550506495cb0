#include "contact/grid_terrain.h"

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <fstream>
#include <sstream>
#include <stdexcept>

namespace plantar::contact {

namespace {
Eigen::MatrixXd read_grid(const std::string& path) {
  std::ifstream in(path);
  if (!in)
    throw std::invalid_argument("GridTerrain: cannot open the terrain grid file '" + path + "'");
  std::vector<std::vector<double>> rows;
  std::string line;
  int line_number = 0;
  while (std::getline(in, line)) {
    ++line_number;
    const auto first = line.find_first_not_of(" \t\r");
    if (first == std::string::npos || line[first] == '#')
      continue;
    std::vector<double> row;
    std::stringstream fields(line);
    std::string field;
    int column = 0;
    while (std::getline(fields, field, ',')) {
      ++column;
      const auto begin = field.find_first_not_of(" \t\r");
      const auto end = field.find_last_not_of(" \t\r");
      const std::string text =
          begin == std::string::npos ? std::string() : field.substr(begin, end - begin + 1);
      char* stop = nullptr;
      const double value = std::strtod(text.c_str(), &stop);
      if (text.empty() || *stop != '\0' || !std::isfinite(value))
        throw std::invalid_argument(
            "GridTerrain: " + path + " line " + std::to_string(line_number) + " column " +
            std::to_string(column) + ": '" + text + "' is not a finite height (m)");
      row.push_back(value);
    }
    if (!rows.empty() && row.size() != rows.front().size())
      throw std::invalid_argument("GridTerrain: " + path + " line " + std::to_string(line_number) +
                                  " has " + std::to_string(row.size()) + " values, expected " +
                                  std::to_string(rows.front().size()) + " (as the first row)");
    rows.push_back(std::move(row));
  }
  if (rows.size() < 2 || rows.front().size() < 2)
    throw std::invalid_argument("GridTerrain: " + path + " has " + std::to_string(rows.size()) +
                                " rows of " +
                                std::to_string(rows.empty() ? 0 : rows.front().size()) +
                                " values, allowed >= 2 rows of >= 2 values");
  Eigen::MatrixXd heights(rows.size(), rows.front().size());
  for (std::size_t r = 0; r < rows.size(); ++r)
    for (std::size_t c = 0; c < rows[r].size(); ++c)
      heights(static_cast<Eigen::Index>(r), static_cast<Eigen::Index>(c)) = rows[r][c];
  return heights;
}
} // namespace

GridTerrain::GridTerrain(const std::string& path, double spacing, const Eigen::Vector2d& origin,
                         double level)
    : heights_(read_grid(path).array() + level), spacing_(spacing), origin_(origin) {
  check(path);
}

GridTerrain::GridTerrain(const Eigen::MatrixXd& heights, double spacing,
                         const Eigen::Vector2d& origin, double level)
    : heights_(heights.array() + level), spacing_(spacing), origin_(origin) {
  check("(heights in memory)");
}

void GridTerrain::check(const std::string& source) const {
  std::ostringstream msg;
  if (!(spacing_ > 0.0) || !std::isfinite(spacing_))
    msg << "GridTerrain: " << source << ": spacing = " << spacing_ << " m, allowed (0, inf)";
  else if (!origin_.allFinite() || !heights_.allFinite())
    msg << "GridTerrain: " << source << ": origin (" << origin_.transpose()
        << ") m and level must be finite";
  else if (heights_.rows() < 2 || heights_.cols() < 2)
    msg << "GridTerrain: " << source << ": " << heights_.rows() << " x " << heights_.cols()
        << " heights, allowed >= 2 x 2";
  if (!msg.str().empty())
    throw std::invalid_argument(msg.str());
}

bool GridTerrain::locate(double x, double y, int& c, int& r, double& u, double& v) const {
  const double gx = (x - origin_.x()) / spacing_, gy = (y - origin_.y()) / spacing_;
  const double last_c = static_cast<double>(heights_.cols() - 1);
  const double last_r = static_cast<double>(heights_.rows() - 1);
  const bool inside = gx >= 0.0 && gx <= last_c && gy >= 0.0 && gy <= last_r;
  const double cx = std::clamp(gx, 0.0, last_c), cy = std::clamp(gy, 0.0, last_r);
  c = std::min(static_cast<int>(cx), static_cast<int>(heights_.cols()) - 2);
  r = std::min(static_cast<int>(cy), static_cast<int>(heights_.rows()) - 2);
  u = cx - c;
  v = cy - r;
  return inside;
}

double GridTerrain::height(double x, double y) const {
  int c, r;
  double u, v;
  locate(x, y, c, r, u, v);
  return (1 - u) * (1 - v) * heights_(r, c) + u * (1 - v) * heights_(r, c + 1) +
         (1 - u) * v * heights_(r + 1, c) + u * v * heights_(r + 1, c + 1);
}

Eigen::Vector2d GridTerrain::gradient(double x, double y) const {
  int c, r;
  double u, v;
  if (!locate(x, y, c, r, u, v))
    return Eigen::Vector2d::Zero();
  const double h00 = heights_(r, c), h10 = heights_(r, c + 1);
  const double h01 = heights_(r + 1, c), h11 = heights_(r + 1, c + 1);
  return Eigen::Vector2d(((1 - v) * (h10 - h00) + v * (h11 - h01)) / spacing_,
                         ((1 - u) * (h01 - h00) + u * (h11 - h10)) / spacing_);
}

} // namespace plantar::contact
