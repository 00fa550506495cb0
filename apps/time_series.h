#pragma once
// A preallocated table of numbers (rows = output samples, named columns), filled in the time
// loop without allocating and written as CSV at the end.

#include <Eigen/Core>

#include <filesystem>
#include <string>
#include <vector>

namespace plantar::app {

class TimeSeries {
public:
  TimeSeries() = default;
  /// @p columns the header, @p max_rows the capacity (allocates once).
  TimeSeries(std::vector<std::string> columns, int max_rows);
  int n_columns() const { return static_cast<int>(columns_.size()); }
  int n_rows() const { return n_rows_; }
  /// Appends a row and returns it for filling (no allocation). Throws std::runtime_error
  /// if the capacity is exhausted.
  Eigen::Ref<Eigen::RowVectorXd> append();
  /// Element (row, column).
  double operator()(int row, int column) const { return values_(row, column); }
  /// Column index of @p name; throws std::invalid_argument if absent.
  int column(const std::string& name) const;
  const std::vector<std::string>& columns() const { return columns_; }
  /// Writes "header\nrow\n..." to @p path atomically (fem/atomic_file.h), each value as the
  /// shortest decimal text that reads back to the same double.
  void write_csv(const std::filesystem::path& path) const;

private:
  std::vector<std::string> columns_;
  Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor> values_;
  int n_rows_ = 0;
};

} // namespace plantar::app
