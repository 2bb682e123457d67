#pragma once
// The MERL isotropic BRDF table (Matusik, Pfister, Brand & McMillan 2003, "A Data-Driven
// Reflectance Model"; format as SPEC §2 `measured` fixes it): f sampled in Rusinkiewicz's
// half/difference angles (Rusinkiewicz 1998, "A New Change of Variables for Efficient
// BRDF Representation") on a 90 × 90 × 180 grid,
//   entry (i, j, k) at θh = ((i + ½)/90)² · π/2,  θd = (j + ½)°,  φd = (k + ½)°,
// φd folded into [0°, 180°) because swapping wi and wo adds 180° to it (reciprocity).
// The θh axis is non-uniform (index = 90 √(θh / (π/2))): the bins crowd near the
// specular peak. On disk: three little-endian int32 (90, 90, 180), then three channels
// (red, green, blue) of 1,458,000 little-endian doubles each, entry k + 180 j + 16200 i,
// each f / scale with scale = 1/1500, 1.15/1500, 1.66/1500; a negative entry was not
// measured.
//
// In memory the table is held as interleaved floats (r, g, b per entry): one lookup
// touches one cache line per entry instead of three far-apart doubles, and loads an entry
// as one vector of four floats (its r, g, b and the next entry's r).

#include <array>
#include <cmath>
#include <cstddef>
#include <span>
#include <string>
#include <utility>
#include <vector>

#include "gonio/color.h"
#include "gonio/math/vec3.h"

namespace gonio {

class OutputFile;

// The table's memory (merl.cpp): blocks of 2 MiB and more aligned to 2 MiB, which Linux is
// asked to back with transparent huge pages (madvise MADV_HUGEPAGE, before the first touch).
// A lookup's entries lie anywhere in the 17.5 MB; on 4 KiB pages (4,300 of them) most
// lookups also missed the TLB. Where the system offers no such pages, ordinary ones.
void* merl_table_allocate(std::size_t bytes);
void merl_table_deallocate(void* p, std::size_t bytes) noexcept;
template <typename T>
struct MerlTableAllocator {
  using value_type = T;
  MerlTableAllocator() = default;
  template <typename U>
  MerlTableAllocator(const MerlTableAllocator<U>&) {}
  T* allocate(std::size_t n) { return static_cast<T*>(merl_table_allocate(n * sizeof(T))); }
  void deallocate(T* p, std::size_t n) noexcept { merl_table_deallocate(p, n * sizeof(T)); }
  friend bool operator==(const MerlTableAllocator&, const MerlTableAllocator&) { return true; }
};

struct MerlTable {
  static constexpr int kThetaH = 90, kThetaD = 90, kPhiD = 180;
  static constexpr std::size_t kEntries = std::size_t(kThetaH) * kThetaD * kPhiD;  // 1,458,000
  // f = stored value × scale, per channel (MERL's reference reader).
  static constexpr std::array<double, 3> kScale = {1.0 / 1500, 1.15 / 1500, 1.66 / 1500};
  // The value stored for an entry that was not measured.
  static constexpr float kMissing = -1;
  // The largest f (1/sr) a table may hold; read_merl refuses an entry above it, write_merl
  // will not write one. Held as float, f must fit FLT_MAX = 3.4e38, and so must what is
  // computed from it in float: the trilinear interpolation (a convex combination, rounded),
  // the sampler's target (the three channels summed, times cos θi: ≤ 3 f), a sample's
  // weight f cos θi / pdf (≤ π f / MeasuredData::kDefensive = 31.4 f, the defensive cosine
  // tenth) and an albedo (a mean of such weights, summed in double, rounded to float). The
  // largest of these, 3 · 31.4 f, stays below FLT_MAX up to f ≈ 3.6e36; 1e30 leaves a
  // factor of 10⁶ besides, for blends and sums of a few lobes. (A MERL entry stores
  // f / scale, so entries up to 1e30 · 1500 = 1.5e33 in the file.)
  static constexpr float kMaxValue = 1e30f;

  // 3 × kEntries floats: f in 1/sr of entry e at rgb[3e .. 3e+2], or kMissing in all three;
  // then one float of padding (0), so that the lookup can load each entry as four floats.
  static constexpr std::size_t kFloats = 3 * kEntries + 1;
  std::vector<float, MerlTableAllocator<float>> rgb = std::vector<float, MerlTableAllocator<float>>(kFloats, 0.0f);

  static constexpr std::size_t index(int i, int j, int k) {
    return std::size_t(k) + std::size_t(kPhiD) * std::size_t(j) + std::size_t(kPhiD) * kThetaD * std::size_t(i);
  }
  bool measured(int i, int j, int k) const { return rgb[3 * index(i, j, k)] >= 0; }
  Color at(int i, int j, int k) const {
    const float* p = &rgb[3 * index(i, j, k)];
    return {p[0], p[1], p[2]};
  }
  void set(int i, int j, int k, const Color& f) {
    float* p = &rgb[3 * index(i, j, k)];
    p[0] = f[0], p[1] = f[1], p[2] = f[2];
  }
  void set_missing(int i, int j, int k) {
    float* p = &rgb[3 * index(i, j, k)];
    p[0] = p[1] = p[2] = kMissing;
  }
};

// Bin centres, in radians.
double merl_theta_h(int i);  // ((i + ½)/90)² · π/2
double merl_theta_d(int j);  // (j + ½)°
double merl_phi_d(int k);    // (k + ½)°

// Rusinkiewicz coordinates of a pair of directions on the same side (z > 0), θh and θd in
// [0, π/2], φd in [0, π) (folded). `wi` is the one rotated into the difference frame.
struct HalfDiff {
  double theta_h, theta_d, phi_d;
};
HalfDiff half_diff(const Vec3& wo, const Vec3& wi);

// The same in precision T, φd unfolded in [−π, π]; `atan2` is the arctangent to use. For
// unit vectors wi = cos θd h + sin θd d and wo = cos θd h − sin θd d, so θd is taken as
// atan2(|wi − wo|, |wi + wo|) and φd as the azimuth of wi − wo in the half vector's frame
// (Rusinkiewicz 1998, §3: rotate by −φh about z, then by −θh about y). Written that way,
// both are exactly symmetric in wo and wi (φd up to π): the table lookup is reciprocal even
// for float inputs a few ulps off unit length, where rotating wi alone (MERL's code) gave
// θd's differing by 2e-4° near grazing.
// atan2 does not change when both arguments are scaled by the same positive number, so
// the half vector is never normalised: θh = atan2(|s_xy|, s_z) for s = wo + wi, and φd's
// arguments are those of the normalised frame times |s| |s_xy| (no division at all).
// Computed in two steps: half_diff_atan2_args gives the arguments (y[n], x[n]) of the three
// arctangents, θh = atan2(y[0], x[0]), θd = atan2(y[1], x[1]), φd = atan2(y[2], x[2]);
// half_diff_angles takes them one by one, the measured model's lookup four at once in one
// vector (measured_data.cpp, with its pdf's).
template <typename T>
void half_diff_atan2_args(const Vec3& wo, const Vec3& wi, T y[3], T x[3]) {
  const T sx = T(wo.x) + T(wi.x), sy = T(wo.y) + T(wi.y), sz = T(wo.z) + T(wi.z);
  const T ex = T(wi.x) - T(wo.x), ey = T(wi.y) - T(wo.y), ez = T(wi.z) - T(wo.z);
  const T sp2 = sx * sx + sy * sy, sp_len = std::sqrt(sp2);
  const T sum = std::sqrt(sp2 + sz * sz);
  y[0] = sp_len, x[0] = sz;
  y[1] = std::sqrt(ex * ex + ey * ey + ez * ez), x[1] = sum;
  // e in the half vector's frame: x1 = (s_xy · e_xy)/|s_xy|, y1 = (s_xy × e_xy)/|s_xy|,
  // φd = atan2(y1, cos θh x1 − sin θh ez). With the half vector along z (s_xy = 0) the
  // frame's x axis is the x axis.
  if (sp2 > 0)
    y[2] = sum * (sx * ey - sy * ex), x[2] = sz * (sx * ex + sy * ey) - sp2 * ez;
  else
    y[2] = ey, x[2] = ex;
}
template <typename T, typename Atan2>
void half_diff_angles(const Vec3& wo, const Vec3& wi, Atan2 atan2, T& theta_h, T& theta_d, T& phi_d) {
  T y[3], x[3];
  half_diff_atan2_args<T>(wo, wi, y, x);
  theta_h = atan2(y[0], x[0]);
  theta_d = atan2(y[1], x[1]);
  phi_d = atan2(y[2], x[2]);
}
// The pair (wo, wi) of the half/difference angles, with φh = 0: the inverse of half_diff
// (either direction may lie below the horizon, z < 0, for large θh + θd).
std::pair<Vec3, Vec3> merl_directions(double theta_h, double theta_d, double phi_d);

// Reads a MERL file. Throws InputError "PATH: ..." (one line) for a file that cannot be
// read, a wrong header, a wrong size, a NaN/Inf entry or one whose f = stored × scale
// exceeds MerlTable::kMaxValue (naming the entry, its channel and its value).
MerlTable read_merl(const std::string& path);
// The same from the file's bytes in memory; `name` (the file, as messages show it)
// prefixes every error.
MerlTable parse_merl(std::span<const unsigned char> bytes, const std::string& name);
// Writes `table` (missing entries as -1 in the file) through an OutputFile
// (gonio/io/output_file.h): a target that is not a regular file is refused, and the table
// takes its name only once written whole. Throws InputError "PATH: ..." on any failure,
// and for an entry read_merl would refuse (not finite, or above MerlTable::kMaxValue), so
// that every table gonio writes reads back.
void write_merl(const std::string& path, const MerlTable& table);
// The same into an output made earlier (so that a bad target is refused before the work).
void write_merl(OutputFile& out, const MerlTable& table);

}  // namespace gonio
