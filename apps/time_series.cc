#include "apps/time_series.h"

#include "fem/atomic_file.h"

#include <charconv>
#include <stdexcept>
#include <vector>

namespace plantar::app {

TimeSeries::TimeSeries(std::vector<std::string> columns, int max_rows)
    : columns_(std::move(columns)), values_(max_rows, static_cast<int>(columns_.size())) {
  values_.setZero();
}

Eigen::Ref<Eigen::RowVectorXd> TimeSeries::append() {
  if (n_rows_ >= values_.rows())
    throw std::runtime_error("TimeSeries: capacity of " + std::to_string(values_.rows()) +
                             " rows exhausted");
  return values_.row(n_rows_++);
}

int TimeSeries::column(const std::string& name) const {
  for (std::size_t i = 0; i < columns_.size(); ++i)
    if (columns_[i] == name)
      return static_cast<int>(i);
  throw std::invalid_argument("TimeSeries: no column '" + name + "'");
}

void TimeSeries::write_csv(const std::filesystem::path& path) const {
  fem::write_file_atomically(path, [&](std::ostream& out) {
    for (std::size_t i = 0; i < columns_.size(); ++i)
      out << (i ? "," : "") << columns_[i];
    out << "\n";
    // Each row formatted into one buffer: the shortest decimal text that reads back to the same
    // double (std::to_chars), at most 24 characters a value.
    std::vector<char> line(25 * static_cast<std::size_t>(values_.cols()) + 1);
    for (int r = 0; r < n_rows_; ++r) {
      char* end = line.data();
      for (int c = 0; c < values_.cols(); ++c) {
        if (c)
          *end++ = ',';
        end = std::to_chars(end, line.data() + line.size(), values_(r, c)).ptr;
      }
      *end++ = '\n';
      out.write(line.data(), end - line.data());
    }
  });
}

} // namespace plantar::app
