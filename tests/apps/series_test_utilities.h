#pragma once
// Comparing time series and reading back cell volumes of .vtu files, for the tests of
// tests/apps.

#include "apps/time_series.h"

#include <vtkCell.h>
#include <vtkDataArray.h>
#include <vtkNew.h>
#include <vtkPointData.h>
#include <vtkPoints.h>
#include <vtkUnstructuredGrid.h>
#include <vtkXMLUnstructuredGridReader.h>

#include <gtest/gtest.h>

#include <Eigen/Dense>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <string>
#include <vector>

namespace plantar::app::testing {

/// max over the columns (the first, time, aside) of max_r |a - b| / max_r |a|: the relative
/// difference of two series of the same shape; entries NaN in both are skipped. Sets
/// @p worst_column (if given) to the name of the column where it is reached. @p only: the
/// columns compared (empty: all).
inline double series_difference(const TimeSeries& a, const TimeSeries& b,
                                std::string* worst_column = nullptr,
                                const std::vector<std::string>& only = {}) {
  EXPECT_EQ(a.n_rows(), b.n_rows());
  EXPECT_EQ(a.n_columns(), b.n_columns());
  double worst = 0;
  for (int c = 1; c < a.n_columns(); ++c) {
    if (!only.empty() && std::find(only.begin(), only.end(), a.columns()[c]) == only.end())
      continue;
    double scale = 0, difference = 0;
    for (int r = 0; r < a.n_rows(); ++r) {
      if (std::isnan(a(r, c)) && std::isnan(b(r, c)))
        continue;
      scale = std::max(scale, std::abs(a(r, c)));
      difference = std::max(difference, std::abs(a(r, c) - b(r, c)));
    }
    if (scale > 0 && difference / scale > worst) {
      worst = difference / scale;
      if (worst_column)
        *worst_column = a.columns()[c];
    }
  }
  return worst;
}

/// Volume of VTK cell @p cell (m^3; tetrahedron: |det| / 6; hexahedron: 6 tetrahedra).
inline double cell_volume(vtkCell* cell) {
  auto point = [&](int i) {
    double x[3];
    cell->GetPoints()->GetPoint(i, x);
    return Eigen::Vector3d(x[0], x[1], x[2]);
  };
  auto tetra = [&](int a, int b, int c, int d) {
    return std::abs((point(b) - point(a)).cross(point(c) - point(a)).dot(point(d) - point(a))) /
           6.0;
  };
  if (cell->GetNumberOfPoints() == 4)
    return tetra(0, 1, 2, 3);
  if (cell->GetNumberOfPoints() == 8) // VTK hexahedron: 0-3 bottom, 4-7 top
    return tetra(0, 1, 2, 6) + tetra(0, 2, 3, 6) + tetra(0, 3, 7, 6) + tetra(0, 7, 4, 6) +
           tetra(0, 4, 5, 6) + tetra(0, 5, 1, 6);
  ADD_FAILURE() << "cell with " << cell->GetNumberOfPoints() << " points";
  return 0;
}

/// int f dV over the cells of the .vtu at @p path for its piecewise-constant field @p name
/// (deal.II writes cell data as point data on each cell's own vertices); NaN, with a test
/// failure, if @p name or one of @p also_present is missing.
inline double vtu_cell_integral(const std::filesystem::path& path, const char* name,
                                const std::vector<const char*>& also_present) {
  vtkNew<vtkXMLUnstructuredGridReader> reader;
  reader->SetFileName(path.c_str());
  reader->Update();
  vtkUnstructuredGrid* grid = reader->GetOutput();
  for (const char* other : also_present)
    EXPECT_NE(grid->GetPointData()->GetArray(other), nullptr) << path << ": " << other;
  vtkDataArray* field = grid->GetPointData()->GetArray(name);
  if (field == nullptr) {
    ADD_FAILURE() << path << ": no array " << name;
    return std::nan("");
  }
  double integral = 0;
  for (vtkIdType c = 0; c < grid->GetNumberOfCells(); ++c) {
    vtkCell* cell = grid->GetCell(c);
    integral += field->GetTuple1(cell->GetPointId(0)) * cell_volume(cell);
  }
  return integral;
}

} // namespace plantar::app::testing
