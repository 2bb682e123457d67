#pragma once
// MERL tables for the tests, written by the tests' own byte-level writer (not gonio's
// write_merl): three little-endian int32 90, 90, 180, then the red, green and blue channels
// of 90·90·180 little-endian doubles, entry k + 180 j + 16200 i, each f / scale with scale
// 1/1500, 1.15/1500, 1.66/1500 (Matusik et al. 2003; SPEC §2). Files go to the temporary
// directory, one name per process.

#include <unistd.h>

#include <cmath>
#include <cstdio>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <functional>
#include <string>
#include <vector>

namespace gonio_test_merl {

constexpr int kTH = 90, kTD = 90, kPD = 180;
constexpr std::size_t kN = std::size_t(kTH) * kTD * kPD;
constexpr double kScale[3] = {1.0 / 1500, 1.15 / 1500, 1.66 / 1500};
constexpr double kPi = 3.14159265358979323846;

// Bin centres (SPEC §2), radians.
inline double theta_h(int i) { return std::pow((i + 0.5) / 90, 2) * kPi / 2; }
inline double theta_d(int j) { return (j + 0.5) * kPi / 180; }
inline double phi_d(int k) { return (k + 0.5) * kPi / 180; }

inline std::string temp_path(const std::string& name) {
  return (std::filesystem::temp_directory_path() /
          ("gonio_test_" + std::to_string(::getpid()) + "_" + name + ".binary"))
      .string();
}

// Raw bytes of a table: value(i, j, k, channel) is f in 1/sr, or negative for "not measured".
inline std::vector<unsigned char> table_bytes(const std::function<double(int, int, int, int)>& value) {
  std::vector<unsigned char> bytes(12 + 3 * kN * 8);
  const std::int32_t dims[3] = {kTH, kTD, kPD};
  for (int d = 0; d < 3; ++d)
    for (int b = 0; b < 4; ++b) bytes[size_t(4 * d + b)] = (std::uint32_t(dims[d]) >> (8 * b)) & 0xff;
  for (int c = 0; c < 3; ++c)
    for (int i = 0; i < kTH; ++i)
      for (int j = 0; j < kTD; ++j)
        for (int k = 0; k < kPD; ++k) {
          const double f = value(i, j, k, c);
          const double stored = f < 0 ? -1.0 : f / kScale[c];
          std::uint64_t u;
          std::memcpy(&u, &stored, 8);
          const std::size_t at = 12 + (std::size_t(c) * kN + std::size_t(k) + 180 * std::size_t(j) + 16200 * std::size_t(i)) * 8;
          for (int b = 0; b < 8; ++b) bytes[at + size_t(b)] = (u >> (8 * b)) & 0xff;
        }
  return bytes;
}

inline void write_bytes(const std::string& path, const std::vector<unsigned char>& bytes) {
  std::ofstream out(path, std::ios::binary | std::ios::trunc);
  out.write(reinterpret_cast<const char*>(bytes.data()), std::streamsize(bytes.size()));
}

// A grey Lambertian table, f = albedo/π everywhere above the surface, written once per
// process: the file the type-by-type sweeps give a `measured` material.
// A file removed when the test process ends.
struct TempTable {
  std::string path;
  explicit TempTable(std::string p) : path(std::move(p)) {}
  ~TempTable() { std::remove(path.c_str()); }
};
inline const std::string& lambert_table() {
  static const TempTable table(temp_path("lambert"));
  static const bool written = (write_bytes(table.path, table_bytes([](int, int, int, int) { return 0.5 / kPi; })), true);
  (void)written;
  return table.path;
}

}  // namespace gonio_test_merl
