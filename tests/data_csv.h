#pragma once
// The tests' own reader of data/'s CSV files ('#' comments, one header line, rows of
// numbers), written without gonio's parsers so that expectations stay independent of them.

#include <gtest/gtest.h>

#include <cctype>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

namespace gonio_test_data {

// The numeric rows of data/<rel>.
inline std::vector<std::vector<double>> read_data(const std::string& rel) {
  std::ifstream in(std::string(GONIO_SOURCE_DIR) + "/data/" + rel);
  EXPECT_TRUE(in.good()) << rel;
  std::vector<std::vector<double>> rows;
  std::string line;
  while (std::getline(in, line)) {
    if (line.empty() || !std::isdigit(static_cast<unsigned char>(line[0]))) continue;
    std::vector<double> r;
    std::stringstream ss(line);
    std::string f;
    while (std::getline(ss, f, ',')) r.push_back(std::stod(f));
    rows.push_back(r);
  }
  return rows;
}

// Linear interpolation in rows (x = column 0, y = column `col`); 0 outside.
inline double lerp_rows(const std::vector<std::vector<double>>& rows, double x, size_t col = 1) {
  for (size_t i = 0; i + 1 < rows.size(); ++i)
    if (rows[i][0] <= x && x <= rows[i + 1][0])
      return rows[i][col] + (x - rows[i][0]) / (rows[i + 1][0] - rows[i][0]) * (rows[i + 1][col] - rows[i][col]);
  return 0;
}

}  // namespace gonio_test_data
