// TimeSeries::write_csv: every value read back from the CSV text (std::strtod) is the double
// that was stored, bit for bit, across the whole range (normal, subnormal, signed zeros,
// infinities, NaN, random bit patterns), and the header and row count are as appended.
#include "apps/time_series.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <limits>
#include <random>
#include <sstream>
#include <string>
#include <unistd.h>
#include <vector>

namespace plantar::app {
namespace {

std::uint64_t bits(double x) {
  std::uint64_t b;
  std::memcpy(&b, &x, sizeof b);
  return b;
}

TEST(TimeSeries, CsvReadsBackEveryDoubleExactly) {
  using limits = std::numeric_limits<double>;
  std::vector<double> values = {0.0,
                                -0.0,
                                0.1,
                                1.0 / 3.0,
                                -2.5e-4,
                                5e-4,
                                568.98,
                                1e21,
                                1e-7,
                                limits::max(),
                                limits::lowest(),
                                limits::min(),
                                limits::denorm_min(),
                                -limits::denorm_min(),
                                limits::infinity(),
                                -limits::infinity(),
                                limits::quiet_NaN()};
  std::mt19937_64 random(42);
  while (values.size() < 3 * 1000) {
    const std::uint64_t b = random();
    double x;
    std::memcpy(&x, &b, sizeof x);
    if (std::isfinite(x))
      values.push_back(x);
  }
  const int columns = 3;
  const int rows = static_cast<int>(values.size()) / columns;
  TimeSeries series({"a", "b", "c"}, rows + 1);
  for (int r = 0; r < rows; ++r) {
    auto row = series.append();
    for (int c = 0; c < columns; ++c)
      row[c] = values[columns * r + c];
  }
  const auto path = std::filesystem::temp_directory_path() /
                    ("plantar_time_series_" + std::to_string(::getpid()) + ".csv");
  series.write_csv(path);
  std::ifstream in(path);
  std::string line;
  ASSERT_TRUE(std::getline(in, line));
  EXPECT_EQ(line, "a,b,c");
  int r = 0;
  while (std::getline(in, line)) {
    ASSERT_LT(r, rows);
    std::stringstream fields(line);
    std::string field;
    for (int c = 0; c < columns; ++c) {
      ASSERT_TRUE(std::getline(fields, field, ',')) << "row " << r;
      const double expected = values[columns * r + c];
      char* end = nullptr;
      const double read = std::strtod(field.c_str(), &end);
      EXPECT_EQ(*end, '\0') << field;
      if (std::isnan(expected))
        EXPECT_TRUE(std::isnan(read)) << field;
      else
        EXPECT_EQ(bits(read), bits(expected)) << field << " for " << expected;
    }
    EXPECT_FALSE(std::getline(fields, field, ',')) << "row " << r << " has more than 3 fields";
    ++r;
  }
  EXPECT_EQ(r, rows);
  std::filesystem::remove(path);
}

} // namespace
} // namespace plantar::app
