// Measured BRDFs (measured_data.h): interpolation in the MERL table and the tabulated
// sampling distribution.

#include "gonio/measured_data.h"

#include <algorithm>
#include <bit>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <map>
#include <mutex>

#include "gonio/math/cdf_guide.h"
#include "gonio/math/fast_atan.h"
#include "gonio/math/select.h"
#include "gonio/math/warp.h"
#include "gonio/merl/coverage.h"
#include "gonio/io/file_cache.h"
#include "gonio/io/notes.h"

namespace gonio {
namespace {

constexpr Float kDegPerRad = Float(180 / kPiD);

}  // namespace

MeasuredData::MeasuredData(MerlTable table, std::string path) : table_(std::move(table)), path_(std::move(path)) {
  // Cells uniform in x = √(sin(θ'/2)): cos θ' = 1 − 2 sin²(θ'/2) = 1 − 2 x⁴ at the edges.
  for (int i = 0; i <= kThetaCells; ++i) {
    const double x = double(i) / kThetaCells;
    cos_edge_[size_t(i)] = float(1 - 2 * x * x * x * x);
  }
  for (int i = 0; i < kThetaCells; ++i) inv_cos_width_[size_t(i)] = 1 / (cos_edge_[size_t(i)] - cos_edge_[size_t(i) + 1]);
  // θo bin b spans t = 1 − √(1 − θo/(π/2)) in [b, b + 1)/kThetaOBins (theta_o_bin): the
  // bin of cos θo = c is the first b with c ≥ bin_cos_lo_[b].
  for (int b = 0; b < kThetaOBins; ++b) {
    const double t = double(b + 1) / kThetaOBins;
    bin_cos_lo_[size_t(b)] = b + 1 == kThetaOBins ? 0.0f : float(std::cos((1 - (1 - t) * (1 - t)) * (kPiD / 2)));
  }
  const auto bin_of_cos = [this](float c) {
    int b = 0;
    while (b + 1 < kThetaOBins && c < bin_cos_lo_[size_t(b)]) ++b;
    return b;
  };
  for (int s = 0; s < kBinLutSize; ++s) bin_lut_[size_t(s)] = std::uint8_t(bin_of_cos(float(s + 1) / kBinLutSize));
  build_sampler();
}

namespace {
// Where (wo, wi) falls in the table: the entry (i0, j0, k0) below it, the step from k0 to
// k1 (3 floats, or back across the φd seam) and the fractions between the neighbours along
// each axis. Its eight neighbours are p00 + {0, kStepJ, kStepI, kStepI + kStepJ} + {0, dk}.
struct TableCorners {
  const float* p00;
  std::ptrdiff_t dk;
  Float ti, tj, tk;  // the fractions along θh, θd, φd
};
constexpr std::ptrdiff_t kStepJ = 3 * MerlTable::kPhiD, kStepI = 3 * MerlTable::kPhiD * MerlTable::kThetaD;

// The half/difference angles (merl.h, half_diff_atan2_args) take three arctangents; a
// fourth pair of arguments (y4, x4) rides along in the same vector (the pdf's azimuth in
// eval) and its arctangent is returned in `extra`. False where the directions have no
// angles (not finite, or |wo + wi| overflows).
inline bool locate(const float* data, const Vec3& wo, const Vec3& wi, Float y4, Float x4, TableCorners& c,
                   Float& extra) {
  Float y[3], x[3];
  half_diff_atan2_args<Float>(wo, wi, y, x);
  // φd has period π (SPEC §2) and atan2(−y, −x) = atan2(y, x) ± π: turning both of its
  // arguments when y < 0 (the sign bit, so −0 too) puts φd in [0, π]. Folding after the
  // arctangent took a branch that random pairs mispredict half the time.
  const std::uint32_t turn = std::bit_cast<std::uint32_t>(y[2]) & 0x80000000u;
  y[2] = std::bit_cast<Float>(std::bit_cast<std::uint32_t>(y[2]) ^ turn);
  x[2] = std::bit_cast<Float>(std::bit_cast<std::uint32_t>(x[2]) ^ turn);
  const Float4 a = fast_atan2(Float4{y[0], y[1], y[2], y4}, Float4{x[0], x[1], x[2], x4});
  extra = a[3];
  // The angles θh, θd, φd (radians; φd in [0, π]) become the table coordinates in one
  // vector, lane by lane the same operations as in scalar: θh's 90 √(θh/(π/2)) − ½ (its
  // square root taken in lane 0 alone), θd's and φd's degrees − ½. NaN or Inf in any of the
  // three fails the finite test (x − x is 0 only for finite x).
  const Int4 finite = (a - a) == Float4{};
  if (!(finite[0] & finite[1] & finite[2])) return false;
  Float4 v = a * Float4{Float(2 / kPiD), kDegPerRad, kDegPerRad, 0};
  v[0] = std::sqrt(v[0]);
  v = v * Float4{Float(MerlTable::kThetaH), 1, 1, 0} - Float4{Float(0.5), Float(0.5), Float(0.5), 0};
  // φd periodic with period 180°: fold the half bin below 0° (w in [−0.5, 179.5]) to the
  // top, to be interpolated across the seam.
  v[2] += v[2] < 0 ? Float(180) : Float(0);
  // Clamped to [0, n − 1] (θh, θd; φd is in range already); the lower index is at most
  // n − 2 (n − 1 for the periodic φd), so that its upper neighbour exists. The minimum is
  // taken before truncation, which is the same for v ≥ 0 and needs no integer minimum.
  constexpr Float kTop = Float(MerlTable::kThetaH - 1);
  static_assert(MerlTable::kThetaH == MerlTable::kThetaD);
  v = v > Float4{} ? v : Float4{};  // also −0 and the unused lane to +0
  v = v < Float4{kTop, kTop, Float(MerlTable::kPhiD), 0} ? v : Float4{kTop, kTop, Float(MerlTable::kPhiD), 0};
  const Float4 lower = {kTop - 1, kTop - 1, Float(MerlTable::kPhiD - 1), 0};
  const Int4 i = __builtin_convertvector(v < lower ? v : lower, Int4);
  const Float4 t = v - __builtin_convertvector(i, Float4);
  c.ti = t[0], c.tj = t[1], c.tk = t[2];
  c.dk = i[2] + 1 == MerlTable::kPhiD ? -3 * std::ptrdiff_t(MerlTable::kPhiD - 1) : 3;
  c.p00 = data + 3 * MerlTable::index(i[0], i[1], i[2]);
  return true;
}
inline Float4 load4(const float* p) {  // r, g, b of the entry at p and the next float
  Float4 v;
  std::memcpy(&v, p, sizeof v);
  return v;
}
// The weighted mean of the measured corners; 0 where none is measured. With all eight
// measured (the common case) it is three rounds of linear interpolation, a chain of three
// multiply-adds instead of eight, on the three channels at once (lane 3 is ignored).
inline Color interpolate(const TableCorners& c) {
  const float* p[8];  // corner n = 4 di + 2 dj + dk
  for (int n = 0; n < 8; ++n) p[n] = c.p00 + ((n & 4) ? kStepI : 0) + ((n & 2) ? kStepJ : 0) + ((n & 1) ? c.dk : 0);
  Float4 v[8];
  for (int n = 0; n < 8; ++n) v[n] = load4(p[n]);
  Float4 lowest = v[0];
  for (int n = 1; n < 8; ++n) lowest = v[n] < lowest ? v[n] : lowest;
  if (!(lowest[0] < 0)) {
    Float4 e[4];
    for (int m = 0; m < 4; ++m) e[m] = v[2 * m] + c.tk * (v[2 * m + 1] - v[2 * m]);
    const Float4 lo = e[0] + c.tj * (e[1] - e[0]), hi = e[2] + c.tj * (e[3] - e[2]);
    const Float4 out = lo + c.ti * (hi - lo);
    return {out[0], out[1], out[2]};
  }
  Float acc[3] = {0, 0, 0}, weight_sum = 0;
  for (int n = 0; n < 8; ++n) {
    if (p[n][0] < 0) continue;  // not measured
    const Float w = ((n & 4) ? c.ti : 1 - c.ti) * ((n & 2) ? c.tj : 1 - c.tj) * ((n & 1) ? c.tk : 1 - c.tk);
    acc[0] += w * p[n][0], acc[1] += w * p[n][1], acc[2] += w * p[n][2];
    weight_sum += w;
  }
  if (!(weight_sum > 0)) return Color(0);
  const Float inv = 1 / weight_sum;
  return {acc[0] * inv, acc[1] * inv, acc[2] * inv};
}
}  // namespace

Color MeasuredData::lookup(const Vec3& wo, const Vec3& wi) const {
  if (!(wo.z > 0) || !(wi.z > 0)) return Color(0);
  TableCorners c;
  Float unused;
  return locate(table_.rgb.data(), wo, wi, 0, 1, c, unused) ? interpolate(c) : Color(0);
}

// --- sampling ------------------------------------------------------------------------

namespace {
// The frame of wi around the mirror direction of wo (wo with azimuth φo): wr, a unit
// vector x' in the plane of incidence perpendicular to wr and leaning up, and y'. In wo's
// own azimuth (φo = 0): wr = (−sin θo, 0, cos θo), x' = (cos θo, 0, sin θo), y' = (0, 1, 0).
struct MirrorFrame {
  Vec3 wr, xp, yp;
};
inline MirrorFrame mirror_frame(const Vec3& wo) {
  const Float so = std::sqrt(wo.x * wo.x + wo.y * wo.y), inv = so > 0 ? 1 / so : Float(0);
  const Float cp = so > 0 ? wo.x * inv : Float(1), sp = wo.y * inv;
  const Float co = wo.z;
  return {Vec3{-wo.x, -wo.y, co}, Vec3{co * cp, co * sp, so}, Vec3{-sp, cp, 0}};
}
}  // namespace

void MeasuredData::build_sampler() {
  constexpr int kNodesT = kThetaCells + 1, kNodesP = kPhiCells + 1;
  const size_t cells = size_t(kThetaCells) * kPhiCells;
  node_.assign(size_t(kThetaOBins) * kNodesT * kNodesP, 0.0f);
  cell_prob_.assign(size_t(kThetaOBins) * cells, 0.0f);
  marginal_cdf_.assign(size_t(kThetaOBins) * (kThetaCells + 1), 0.0f);
  conditional_cdf_.assign(size_t(kThetaOBins) * kThetaCells * (kPhiCells + 1), 0.0f);
  marginal_guide_.assign(size_t(kThetaOBins) * kThetaGuide, 0);
  conditional_guide_.assign(size_t(kThetaOBins) * kThetaCells * kPhiGuide, 0);
  const double dphi = kPiD / kPhiCells;
  for (int b = 0; b < kThetaOBins; ++b) {
    // Bin centre in t = 1 − √(1 − θo/(π/2)) (theta_o_bin).
    const double t = (b + 0.5) / kThetaOBins;
    const double theta_o = (1 - (1 - t) * (1 - t)) * (kPiD / 2);
    const Vec3 wo{Float(std::sin(theta_o)), 0, Float(std::cos(theta_o))};
    const MirrorFrame fr = mirror_frame(wo);
    // The target f cos θi (summed over channels) at the nodes.
    float* node = &node_[size_t(b) * kNodesT * kNodesP];
    for (int it = 0; it < kNodesT; ++it) {
      const double ct = cos_edge_[size_t(it)], st = std::sqrt(std::max(0.0, 1 - ct * ct));
      for (int ip = 0; ip < kNodesP; ++ip) {
        const double ph = ip * dphi;
        const Vec3 wi = normalize(Float(ct) * fr.wr + Float(st * std::cos(ph)) * fr.xp + Float(st * std::sin(ph)) * fr.yp);
        const Color f = wi.z > 0 ? lookup(wo, wi) : Color(0);
        node[it * kNodesP + ip] = wi.z > 0 ? (f[0] + f[1] + f[2]) * wi.z : 0.0f;
      }
    }
    // Each cell's mass: ∫ of the bilinear patch over it = area × mean of its corners
    // (area in (cos θ', φ'), which is solid angle).
    float* prob = &cell_prob_[size_t(b) * cells];
    double total = 0;
    for (int it = 0; it < kThetaCells; ++it)
      for (int ip = 0; ip < kPhiCells; ++ip) {
        const double mean = (double(node[it * kNodesP + ip]) + node[it * kNodesP + ip + 1] + node[(it + 1) * kNodesP + ip] +
                             node[(it + 1) * kNodesP + ip + 1]) / 4;
        const double mass = mean * (cos_edge_[size_t(it)] - cos_edge_[size_t(it) + 1]) * dphi;
        prob[size_t(it) * kPhiCells + size_t(ip)] = float(mass);
        total += mass;
      }
    has_table_[size_t(b)] = total > 0 && std::isfinite(total);
    if (!has_table_[size_t(b)]) continue;
    for (int n = 0; n < kNodesT * kNodesP; ++n) node[n] = float(node[n] / total);
    float* marginal = &marginal_cdf_[size_t(b) * (kThetaCells + 1)];
    double run = 0;
    for (int it = 0; it < kThetaCells; ++it) {
      float* cond = &conditional_cdf_[(size_t(b) * kThetaCells + size_t(it)) * (kPhiCells + 1)];
      double row = 0;
      for (int ip = 0; ip < kPhiCells; ++ip) {
        float& p = prob[size_t(it) * kPhiCells + size_t(ip)];
        p = float(p / total);
        row += p;
      }
      double c = 0;
      for (int ip = 0; ip < kPhiCells; ++ip) {
        c += prob[size_t(it) * kPhiCells + size_t(ip)];
        cond[ip + 1] = row > 0 ? float(c / row) : float(ip + 1) / kPhiCells;
      }
      cond[kPhiCells] = 1;
      build_cdf_guide<kPhiCells, kPhiGuide>(cond, &conditional_guide_[(size_t(b) * kThetaCells + size_t(it)) * kPhiGuide]);
      run += row;
      marginal[it + 1] = float(run);
    }
    marginal[kThetaCells] = 1;
    build_cdf_guide<kThetaCells, kThetaGuide>(marginal, &marginal_guide_[size_t(b) * kThetaGuide]);
  }
}

// The θo bin of wo: uniform in t = 1 − √(1 − θo/(π/2)), so that the bins narrow towards
// grazing, where a lobe changes fastest with θo (the last of 32 spans 89.91° to 90°).
// Found from cos θo = wo.z without an arctangent: a table over cos θo in kBinLutSize steps
// gives the bin at each step's upper end; every bin is wider than a step (the narrowest,
// the last, spans 0.0016 in cos θo), so at most one edge lies below and one comparison
// settles it (the loop is only a guard). wo.z is taken as cos θo: sample and pdf agree
// for any wo, and for unit vectors (as callers pass them) it is exact.
int MeasuredData::theta_o_bin(const Vec3& wo) const {
  const Float c = wo.z > 0 ? std::min(wo.z, Float(1)) : Float(0);  // NaN: 0
  const int step = std::min(int(c * Float(kBinLutSize)), kBinLutSize - 1);
  int b = bin_lut_[size_t(step > 0 ? step : 0)];
  while (b + 1 < kThetaOBins && c < bin_cos_lo_[size_t(b)]) ++b;
  return b;
}

namespace {
// A sample of the density ∝ (1 − x) a + x b on [0, 1] by inverting its CDF, in the form
// that stays accurate when a or b is 0 (pbrt-v4, SampleLinear).
inline Float sample_linear(Float u, Float a, Float b) {
  if (!(a + b > 0)) return u;  // no mass on this segment: any point is as good
  if (u == 0 && a == 0) return 0;
  const Float x = u * (a + b) / (a + std::sqrt(std::max(Float(0), (1 - u) * a * a + u * b * b)));
  return std::min(x, kOneMinusEpsilon);
}
}  // namespace

namespace {
// The arguments of the arctangent of the pdf's azimuth φ' around the mirror direction
// (mirror_frame's x', y'), before folding. Both are scaled by |wo_xy| > 0, which leaves
// the angle and saves a square root and a division; at normal incidence x' = (cos θo, 0, 0)
// and y' = (0, 1, 0) as in mirror_frame.
inline void pdf_azimuth_args(const Vec3& wo, const Vec3& wi, Float& along_y, Float& along_x) {
  const Float so2 = wo.x * wo.x + wo.y * wo.y;
  along_y = so2 > 0 ? wo.x * wi.y - wo.y * wi.x : wi.y;
  along_x = so2 > 0 ? wo.z * (wo.x * wi.x + wo.y * wi.y) + so2 * wi.z : wo.z * wi.x;
}
}  // namespace

Float MeasuredData::tabulated_pdf(const Vec3& wo, const Vec3& wi, int b, Float azimuth) const {
  constexpr int kNodesP = kPhiCells + 1;
  // The chord |wi − wr| = 2 sin(θ'/2) gives the cell coordinate x = √(sin(θ'/2)) and
  // cos θ' = 1 − |wi − wr|²/2 without an arccosine, and accurately near the peak.
  const Vec3 d{wi.x + wo.x, wi.y + wo.y, wi.z - wo.z};  // wi − wr, wr = (−wo.x, −wo.y, wo.z)
  const Float chord2 = dot(d, d), half_chord = std::sqrt(chord2) / 2;
  const Float c = 1 - chord2 / 2;
  // The azimuth folded into [0, π] by the mirror symmetry through the plane of incidence.
  const Float rel = std::abs(azimuth);
  const Float x = std::sqrt(std::min(half_chord, Float(1)));
  if (!std::isfinite(x + rel)) return 0;
  const int it = std::clamp(int(x * kThetaCells), 0, kThetaCells - 1);
  const Float pc = rel * Float(kPhiCells / kPiD);
  const int ip = std::clamp(int(pc), 0, kPhiCells - 1);
  // Bilinear between the cell's corners, in (cos θ', φ').
  const Float c0 = cos_edge_[size_t(it)];
  const Float tu = std::clamp((c0 - c) * inv_cos_width_[size_t(it)], Float(0), Float(1));
  const Float tp = std::clamp(pc - Float(ip), Float(0), Float(1));
  const float* n = &node_[(size_t(b) * (kThetaCells + 1) + size_t(it)) * kNodesP + size_t(ip)];
  const Float v = (1 - tu) * ((1 - tp) * n[0] + tp * n[1]) + tu * ((1 - tp) * n[kNodesP] + tp * n[kNodesP + 1]);
  return v / 2;  // the cell and its mirror image share the mass
}

Float MeasuredData::mixture_pdf(const Vec3& wo, const Vec3& wi, int b, Float azimuth) const {
  if (!has_table_[size_t(b)]) return cosine_hemisphere_pdf(wi.z);
  return kDefensive * cosine_hemisphere_pdf(wi.z) + (1 - kDefensive) * tabulated_pdf(wo, wi, b, azimuth);
}

// Flattened: with the lookup and the pdf inlined into one body, the processor sees their two
// independent chains of square roots and divisions together and overlaps them (7% faster
// than calls, bench_measured.cpp). The pdf's arctangent is the fourth lane of the lookup's
// vector of arctangents (locate), bit for bit the scalar one pdf takes.
[[gnu::flatten]] MeasuredData::Eval MeasuredData::eval(const Vec3& wo, const Vec3& wi) const {
  if (!(wo.z > 0) || !(wi.z > 0)) return {Color(0), 0};
  Float along_y, along_x;
  pdf_azimuth_args(wo, wi, along_y, along_x);
  // The table entries are 17.5 MB apart at random: ask for them first, compute the pdf
  // while they arrive, then interpolate.
  TableCorners c;
  Float azimuth;
  const bool found = locate(table_.rgb.data(), wo, wi, along_y, along_x, c, azimuth);
  if (found)
    for (const float* q : {c.p00, c.p00 + kStepJ, c.p00 + kStepI, c.p00 + kStepI + kStepJ}) {
      __builtin_prefetch(q);
      __builtin_prefetch(q + c.dk);
    }
  const Float p = mixture_pdf(wo, wi, theta_o_bin(wo), azimuth);
  return {found ? interpolate(c) : Color(0), p};
}

Float MeasuredData::pdf(const Vec3& wo, const Vec3& wi) const {
  if (!(wo.z > 0) || !(wi.z > 0)) return 0;
  const int b = theta_o_bin(wo);
  if (!has_table_[size_t(b)]) return cosine_hemisphere_pdf(wi.z);  // no arctangent needed
  Float along_y, along_x;
  pdf_azimuth_args(wo, wi, along_y, along_x);
  return mixture_pdf(wo, wi, b, fast_atan2(along_y, along_x));
}

Vec3 MeasuredData::sample(const Vec3& wo, Float u_lobe, Float u1, Float u2) const {
  constexpr int kNodesP = kPhiCells + 1;
  const int b = theta_o_bin(wo);
  const Float c = has_table_[size_t(b)] ? kDefensive : Float(1);
  if (u_lobe < c) return square_to_cosine_hemisphere(u1, u2);
  const Float u_mirror = (u_lobe - c) / (1 - c);
  // The cell, from the discrete distribution of the patches' masses; the remainders of u1
  // and u2 place the point within it.
  const float* marginal = &marginal_cdf_[size_t(b) * (kThetaCells + 1)];
  const int it = cdf_interval_guided<kThetaCells, kThetaGuide>(marginal, &marginal_guide_[size_t(b) * kThetaGuide], u1);
  const Float m0 = marginal[it], m1 = marginal[it + 1];
  const Float v1 = m1 > m0 ? std::clamp((u1 - m0) / (m1 - m0), Float(0), kOneMinusEpsilon) : Float(0.5);
  const float* cond = &conditional_cdf_[(size_t(b) * kThetaCells + size_t(it)) * (kPhiCells + 1)];
  const int ip = cdf_interval_guided<kPhiCells, kPhiGuide>(
      cond, &conditional_guide_[(size_t(b) * kThetaCells + size_t(it)) * kPhiGuide], u2);
  const Float c0 = cond[ip], c1 = cond[ip + 1];
  const Float v2 = c1 > c0 ? std::clamp((u2 - c0) / (c1 - c0), Float(0), kOneMinusEpsilon) : Float(0.5);
  // Within the bilinear patch (corners n00, n01 along φ', n10, n11 one row down in cos θ'):
  // first the cos θ' coordinate from its linear marginal, then φ' given it (pbrt-v4,
  // SampleBilinear).
  const float* n = &node_[(size_t(b) * (kThetaCells + 1) + size_t(it)) * kNodesP + size_t(ip)];
  const Float tu = sample_linear(v1, n[0] + n[1], n[kNodesP] + n[kNodesP + 1]);
  const Float tp = sample_linear(v2, (1 - tu) * n[0] + tu * n[kNodesP], (1 - tu) * n[1] + tu * n[kNodesP + 1]);
  const Float ct = cos_edge_[size_t(it)] + (cos_edge_[size_t(it) + 1] - cos_edge_[size_t(it)]) * tu;
  const Float st = std::sqrt(std::max(Float(0), 1 - ct * ct));
  // The azimuth φ' = (ip + tp) π / kPhiCells in [0, π], as a fraction of a turn for the
  // polynomial sine and cosine (a libm call costs ~15 ns); its mirror image has −sin φ'.
  const SinCos turn = sincos_2pi((Float(ip) + tp) * Float(0.5 / kPhiCells));
  const Float sin_rel = u_mirror < Float(0.5) ? -turn.sin : turn.sin;
  const MirrorFrame fr = mirror_frame(wo);
  return normalize(ct * fr.wr + (st * turn.cos) * fr.xp + (st * sin_rel) * fr.yp);
}

// --- loading -----------------------------------------------------------------------

std::shared_ptr<const MeasuredData> load_measured(const std::string& path) {
  return cached_file<MeasuredData>(path, [&] {
    auto data = std::make_shared<const MeasuredData>(read_merl(path), path);
    if (const double missing = merl_missing_fraction(data->table()); missing > 0) {
      char pct[32];
      std::snprintf(pct, sizeof pct, "%.3g%%", 100 * missing);
      note("warning: " + path + ": " + pct +
           " of the table's entries above the horizon are missing; the measured model interpolates from measured "
           "neighbours and reads f = 0 where all eight are missing");
    }
    return data;
  });
}

namespace {
// merl_entry_above_horizon's two factors at the bin's centre (merl.h: θh = ((i + ½)/90)² 90°,
// θd = (j + ½)°, φd = (k + ½)°): tan θh tan θd, and |cos φd|.
double centre_tangents(int i, int j) { return std::tan(merl_theta_h(i)) * std::tan(merl_theta_d(j)); }
double centre_cos_phi_d(int k) { return std::abs(std::cos(merl_phi_d(k))); }
}  // namespace

bool merl_entry_above_horizon(int i, int j, int k) { return centre_tangents(i, j) * centre_cos_phi_d(k) < 1; }

double merl_missing_fraction(const MerlTable& table) {
  std::array<double, MerlTable::kPhiD> cos_phi{};
  for (int k = 0; k < MerlTable::kPhiD; ++k) cos_phi[size_t(k)] = centre_cos_phi_d(k);
  std::size_t above = 0, missing = 0;
  for (int i = 0; i < MerlTable::kThetaH; ++i)
    for (int j = 0; j < MerlTable::kThetaD; ++j) {
      const double t = centre_tangents(i, j);
      for (int k = 0; k < MerlTable::kPhiD; ++k) {
        if (!(t * cos_phi[size_t(k)] < 1)) continue;
        ++above;
        if (!table.measured(i, j, k)) ++missing;
      }
    }
  return above ? double(missing) / double(above) : 0.0;
}

}  // namespace gonio
