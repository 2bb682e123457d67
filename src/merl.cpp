// The MERL table format (merl.h): reading, writing, and the half/difference angles.

#include "gonio/merl.h"

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <string_view>
#include <system_error>
#include <filesystem>
#include <limits>
#include <new>
#include <optional>
#include <cstdlib>

#if defined(__linux__)
#include <sys/mman.h>
#endif

#include "gonio/error.h"
#include "gonio/io/output_file.h"
#include "gonio/math/constants.h"

namespace gonio {
namespace {

constexpr double kDeg = kPiD / 180;
constexpr std::size_t kHeaderBytes = 3 * sizeof(std::int32_t);
constexpr std::size_t kFileBytes = kHeaderBytes + 3 * MerlTable::kEntries * sizeof(double);

// The file is little-endian whatever the host.
template <typename T>
T from_little_endian(const unsigned char* p) {
  std::array<unsigned char, sizeof(T)> b;
  std::memcpy(b.data(), p, sizeof(T));
  if constexpr (std::endian::native == std::endian::big) std::reverse(b.begin(), b.end());
  T v;
  std::memcpy(&v, b.data(), sizeof(T));
  return v;
}
template <typename T>
void to_little_endian(T v, unsigned char* p) {
  std::memcpy(p, &v, sizeof(T));
  if constexpr (std::endian::native == std::endian::big) std::reverse(p, p + sizeof(T));
}

std::string quoted(const std::string& path) { return escape_control(path); }

// "MERL entry (i, j, k) of channel c" for entry e of channel c.
std::string entry_name(std::size_t e, int c) {
  const std::size_t i = e / (MerlTable::kThetaD * MerlTable::kPhiD), j = e / MerlTable::kPhiD % MerlTable::kThetaD,
                    k = e % MerlTable::kPhiD;
  return "MERL entry (" + std::to_string(i) + ", " + std::to_string(j) + ", " + std::to_string(k) + ") of channel " +
         "rgb"[c];
}

// Why an entry of f = `f` (1/sr) cannot be in a table, or nothing. A negative entry is
// "not measured", whatever its size.
std::optional<std::string> f_problem(double f) {
  if (!std::isfinite(f)) return "f = " + format_number(f);
  // Compared as the float the table holds, so that a value rounding to the bound is the
  // bound (a table written at it reads back); float(f) is taken only where it exists.
  if (f > double(std::numeric_limits<float>::max()) || float(f) > MerlTable::kMaxValue) {
    char bound[16];  // the float bound as it was typed (1e+30), not to 9 digits
    std::snprintf(bound, sizeof bound, "%g", double(MerlTable::kMaxValue));
    return "f = " + format_number(f) + " 1/sr, above the largest a table may hold (" + bound + ")";
  }
  return std::nullopt;
}

}  // namespace

namespace {
constexpr std::size_t kHugePage = std::size_t(2) << 20;
}  // namespace

void* merl_table_allocate(std::size_t bytes) {
  if (bytes < kHugePage) return ::operator new(bytes);
  const std::size_t size = (bytes + kHugePage - 1) / kHugePage * kHugePage;
  void* p = std::aligned_alloc(kHugePage, size);
  if (!p) throw std::bad_alloc();
#if defined(__linux__) && defined(MADV_HUGEPAGE)
  (void)madvise(p, size, MADV_HUGEPAGE);  // advice only: refused, the pages are ordinary ones
#endif
  return p;
}
void merl_table_deallocate(void* p, std::size_t bytes) noexcept {
  if (bytes < kHugePage) ::operator delete(p);
  else std::free(p);
}

double merl_theta_h(int i) {
  const double x = (i + 0.5) / MerlTable::kThetaH;
  return x * x * (kPiD / 2);
}
double merl_theta_d(int j) { return (j + 0.5) * kDeg; }
double merl_phi_d(int k) { return (k + 0.5) * kDeg; }

HalfDiff half_diff(const Vec3& wo, const Vec3& wi) {
  double th, td, pd;
  half_diff_angles<double>(wo, wi, [](double y, double x) { return std::atan2(y, x); }, th, td, pd);
  if (!(th == th)) return {0, kPiD / 2, 0};  // opposite directions: no half vector
  if (pd < 0) pd += kPiD;  // fold: (φd + π) is the same entry by reciprocity
  if (pd >= kPiD) pd -= kPiD;
  return {th, std::min(td, kPiD / 2), pd};
}

std::pair<Vec3, Vec3> merl_directions(double theta_h, double theta_d, double phi_d) {
  // d in the half-vector frame, then rotated by θh about y (φh = 0); wo is d mirrored
  // through h: wo = 2 (h·d) h − d.
  const double st = std::sin(theta_d), ct = std::cos(theta_d);
  const double dx = st * std::cos(phi_d), dy = st * std::sin(phi_d), dz = ct;
  const double sh = std::sin(theta_h), ch = std::cos(theta_h);
  const double ix = ch * dx + sh * dz, iy = dy, iz = -sh * dx + ch * dz;
  const double hx = sh, hy = 0, hz = ch;
  const double hd = hx * ix + hy * iy + hz * iz;
  const double ox = 2 * hd * hx - ix, oy = 2 * hd * hy - iy, oz = 2 * hd * hz - iz;
  return {Vec3{Float(ox), Float(oy), Float(oz)}, Vec3{Float(ix), Float(iy), Float(iz)}};
}

MerlTable parse_merl(std::span<const unsigned char> bytes, const std::string& name) {
  if (bytes.size() < kHeaderBytes) throw InputError(name + ": not a MERL table: shorter than its 12-byte header");
  const std::int32_t dims[3] = {from_little_endian<std::int32_t>(bytes.data()),
                                from_little_endian<std::int32_t>(bytes.data() + 4),
                                from_little_endian<std::int32_t>(bytes.data() + 8)};
  if (dims[0] != MerlTable::kThetaH || dims[1] != MerlTable::kThetaD || dims[2] != MerlTable::kPhiD)
    throw InputError(name + ": not a MERL table: header says " + std::to_string(dims[0]) + " x " +
                     std::to_string(dims[1]) + " x " + std::to_string(dims[2]) + ", expected 90 x 90 x 180");
  if (bytes.size() < kFileBytes)
    throw InputError(name + ": truncated MERL table: " + std::to_string(bytes.size()) + " bytes, expected " +
                     std::to_string(kFileBytes));
  if (bytes.size() > kFileBytes)
    throw InputError(name + ": MERL table longer than " + std::to_string(kFileBytes) + " bytes (trailing data)");
  MerlTable table;
  for (int c = 0; c < 3; ++c) {
    const unsigned char* channel = bytes.data() + kHeaderBytes + std::size_t(c) * MerlTable::kEntries * sizeof(double);
    for (std::size_t e = 0; e < MerlTable::kEntries; ++e) {
      const double v = from_little_endian<double>(channel + e * sizeof(double));
      if (!std::isfinite(v)) throw InputError(name + ": " + entry_name(e, c) + " is " + format_number(v));
      if (v < 0) {  // not measured, whatever its size
        table.rgb[3 * e + c] = MerlTable::kMissing;
        continue;
      }
      if (const auto problem = f_problem(v * MerlTable::kScale[c]))
        throw InputError(name + ": " + entry_name(e, c) + " is " + format_number(v) + ": " + *problem);
      table.rgb[3 * e + c] = float(v * MerlTable::kScale[c]);
    }
  }
  // An entry missing in one channel is missing in all: an interpolation must not mix a
  // measured red with an unmeasured blue.
  for (std::size_t e = 0; e < MerlTable::kEntries; ++e) {
    float* p = &table.rgb[3 * e];
    if (p[0] < 0 || p[1] < 0 || p[2] < 0) p[0] = p[1] = p[2] = MerlTable::kMissing;
  }
  return table;
}

MerlTable read_merl(const std::string& path) {
  const std::string name = quoted(path);
  std::error_code ec;
  if (std::filesystem::is_directory(path, ec)) throw InputError(name + ": is a directory, not a MERL table");
  // Only regular files: a FIFO or a terminal could block the reader forever.
  if (std::filesystem::exists(path, ec) && !std::filesystem::is_regular_file(path, ec))
    throw InputError(name + ": not a regular file, cannot be a MERL table");
  std::ifstream in(path, std::ios::binary);
  if (!in) throw InputError(name + ": cannot open the MERL table (" + std::string(std::strerror(errno)) + ")");
  // One byte more than a table: enough to tell a longer file, never more.
  std::vector<unsigned char> bytes(kFileBytes + 1);
  in.read(reinterpret_cast<char*>(bytes.data()), std::streamsize(bytes.size()));
  bytes.resize(std::size_t(in.gcount()));
  return parse_merl(bytes, name);
}

void write_merl(const std::string& path, const MerlTable& table) {
  OutputFile out(path, "the table");
  write_merl(out, table);
}

void write_merl(OutputFile& out, const MerlTable& table) {
  std::vector<unsigned char> bytes(kFileBytes);
  // What read_merl would refuse is not written: a table gonio writes reads back.
  for (int c = 0; c < 3; ++c)
    for (std::size_t e = 0; e < MerlTable::kEntries; ++e) {
      const float f = table.rgb[3 * e + c];
      if (f < 0) continue;
      if (const auto problem = f_problem(double(f)))
        throw InputError(quoted(out.path()) + ": cannot write " + entry_name(e, c) + ": " + *problem);
    }
  const std::int32_t dims[3] = {MerlTable::kThetaH, MerlTable::kThetaD, MerlTable::kPhiD};
  for (int d = 0; d < 3; ++d) to_little_endian(dims[d], bytes.data() + 4 * d);
  for (int c = 0; c < 3; ++c) {
    unsigned char* channel = bytes.data() + kHeaderBytes + std::size_t(c) * MerlTable::kEntries * sizeof(double);
    for (std::size_t e = 0; e < MerlTable::kEntries; ++e) {
      const float f = table.rgb[3 * e + c];
      const double stored = f < 0 ? -1.0 : double(f) / MerlTable::kScale[c];
      to_little_endian(stored, channel + e * sizeof(double));
    }
  }
  // Written beside the target and renamed over it, every write checked (OutputFile): a
  // failed write never leaves a truncated table under the name, nor a temporary.
  out.commit(std::string_view(reinterpret_cast<const char*>(bytes.data()), bytes.size()));
}

}  // namespace gonio
