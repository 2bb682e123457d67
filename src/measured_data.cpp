// Measured BRDFs (measured_data.h): interpolation in the MERL table and the tabulated
// sampling distribution.

#include "gonio/measured_data.h"

#include <algorithm>
#include <filesystem>
#include <map>
#include <mutex>

#include "gonio/math/fast_atan.h"
#include "gonio/math/warp.h"

namespace gonio {
namespace {

constexpr Float kDegPerRad = Float(180 / kPiD);

// Half vector and difference angles of (wo, wi), both z > 0, in float: the hot path of
// lookup (merl.h, half_diff_angles).
struct HalfDiffF {
  Float theta_h, theta_d, phi_d;  // radians; φd in [−π, π] (not folded)
};
inline HalfDiffF half_diff_f(const Vec3& wo, const Vec3& wi) {
  HalfDiffF a;
  half_diff_angles<Float>(wo, wi, [](Float y, Float x) { return fast_atan2(y, x); }, a.theta_h, a.theta_d, a.phi_d);
  return a;
}

// Linear interpolation coordinate clamped to [0, n − 1]: index and fraction.
inline void clamp_coord(Float c, int n, int& i0, Float& t) {
  c = std::clamp(c, Float(0), Float(n - 1));
  i0 = std::min(int(c), n - 2);
  t = c - Float(i0);
}

}  // namespace

MeasuredData::MeasuredData(MerlTable table, std::string path) : table_(std::move(table)), path_(std::move(path)) {
  // Cells uniform in x = √(sin(θ'/2)): cos θ' = 1 − 2 sin²(θ'/2) = 1 − 2 x⁴ at the edges.
  for (int i = 0; i <= kThetaCells; ++i) {
    const double x = double(i) / kThetaCells;
    cos_edge_[size_t(i)] = float(1 - 2 * x * x * x * x);
  }
  build_sampler();
}

Color MeasuredData::lookup(const Vec3& wo, const Vec3& wi) const {
  if (!(wo.z > 0) || !(wi.z > 0)) return Color(0);
  const HalfDiffF a = half_diff_f(wo, wi);
  // Directions that are not finite (or overflow |wo + wi|) have no angles.
  if (!std::isfinite(a.theta_h + a.theta_d + a.phi_d)) return Color(0);
  int i0, j0;
  Float ti, tj;
  clamp_coord(Float(MerlTable::kThetaH) * std::sqrt(a.theta_h * Float(2 / kPiD)) - Float(0.5), MerlTable::kThetaH, i0,
              ti);
  clamp_coord(a.theta_d * kDegPerRad - Float(0.5), MerlTable::kThetaD, j0, tj);
  // φd periodic with period 180°: fold, then interpolate across the seam.
  Float w = a.phi_d * kDegPerRad - Float(0.5);  // in [−180.5, 179.5]
  if (w < 0) w += Float(180);
  if (w < 0) w += Float(180);
  int k0 = std::min(int(w), MerlTable::kPhiD - 1);
  const Float tk = std::clamp(w - Float(k0), Float(0), Float(1));
  const int k1 = k0 + 1 == MerlTable::kPhiD ? 0 : k0 + 1;
  const float* data = table_.rgb.data();
  Float acc[3] = {0, 0, 0}, weight_sum = 0;
  for (int di = 0; di < 2; ++di) {
    const Float wi_ = di ? ti : 1 - ti;
    for (int dj = 0; dj < 2; ++dj) {
      const Float wij = wi_ * (dj ? tj : 1 - tj);
      const std::size_t row = MerlTable::index(i0 + di, j0 + dj, 0);
      for (int dk = 0; dk < 2; ++dk) {
        const Float wt = wij * (dk ? tk : 1 - tk);
        const float* p = data + 3 * (row + std::size_t(dk ? k1 : k0));
        if (p[0] < 0) continue;  // not measured
        acc[0] += wt * p[0], acc[1] += wt * p[1], acc[2] += wt * p[2];
        weight_sum += wt;
      }
    }
  }
  if (!(weight_sum > 0)) return Color(0);
  const Float inv = 1 / weight_sum;
  return {acc[0] * inv, acc[1] * inv, acc[2] * inv};
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
      run += row;
      marginal[it + 1] = float(run);
    }
    marginal[kThetaCells] = 1;
  }
}

namespace {
// The index of the CDF interval holding u (cdf[0] = 0, cdf[n] = 1), skipping empty ones.
inline int find_interval(const float* cdf, int n, Float u) {
  const float* it = std::upper_bound(cdf + 1, cdf + n + 1, float(u));
  return std::clamp(int(it - cdf) - 1, 0, n - 1);
}
// The θo bin of wo: uniform in t = 1 − √(1 − θo/(π/2)), so that the bins narrow towards
// grazing, where a lobe changes fastest with θo (the last of 32 spans 89.91° to 90°).
inline int theta_o_bin(const Vec3& wo, int bins) {
  const Float s = 1 - fast_atan2(std::sqrt(wo.x * wo.x + wo.y * wo.y), wo.z) * Float(2 / kPiD);
  const Float t = (1 - std::sqrt(std::max(s, Float(0)))) * Float(bins);
  return t > 0 ? std::min(int(t), bins - 1) : 0;  // NaN: bin 0
}
}  // namespace

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

Float MeasuredData::tabulated_pdf(const Vec3& wo, const Vec3& wi) const {
  constexpr int kNodesP = kPhiCells + 1;
  const int b = theta_o_bin(wo, kThetaOBins);
  if (!has_table_[size_t(b)]) return 0;
  const MirrorFrame fr = mirror_frame(wo);
  // The chord |wi − wr| = 2 sin(θ'/2) gives the cell coordinate x = √(sin(θ'/2)) and
  // cos θ' = 1 − |wi − wr|²/2 without an arccosine, and accurately near the peak.
  const Vec3 d = wi - fr.wr;
  const Float chord2 = dot(d, d), half_chord = std::sqrt(chord2) / 2;
  const Float c = 1 - chord2 / 2;
  // The azimuth around wr, folded into [0, π] by the mirror symmetry through the plane of
  // incidence.
  const Float rel = std::abs(fast_atan2(dot(wi, fr.yp), dot(wi, fr.xp)));
  const Float x = std::sqrt(std::min(half_chord, Float(1)));
  if (!std::isfinite(x + rel)) return 0;
  const int it = std::clamp(int(x * kThetaCells), 0, kThetaCells - 1);
  const Float pc = rel * Float(kPhiCells / kPiD);
  const int ip = std::clamp(int(pc), 0, kPhiCells - 1);
  // Bilinear between the cell's corners, in (cos θ', φ').
  const Float c0 = cos_edge_[size_t(it)], c1 = cos_edge_[size_t(it) + 1];
  const Float tu = c0 > c1 ? std::clamp((c0 - c) / (c0 - c1), Float(0), Float(1)) : Float(0);
  const Float tp = std::clamp(pc - Float(ip), Float(0), Float(1));
  const float* n = &node_[(size_t(b) * (kThetaCells + 1) + size_t(it)) * kNodesP + size_t(ip)];
  const Float v = (1 - tu) * ((1 - tp) * n[0] + tp * n[1]) + tu * ((1 - tp) * n[kNodesP] + tp * n[kNodesP + 1]);
  return v / 2;  // the cell and its mirror image share the mass
}

MeasuredData::Eval MeasuredData::eval(const Vec3& wo, const Vec3& wi) const {
  // Both in one function, so that the compiler inlines them and the processor overlaps the
  // table lookup's wait for memory with the pdf's arithmetic.
  return {lookup(wo, wi), pdf(wo, wi)};
}

Float MeasuredData::pdf(const Vec3& wo, const Vec3& wi) const {
  if (!(wo.z > 0) || !(wi.z > 0)) return 0;
  const int b = theta_o_bin(wo, kThetaOBins);
  const Float c = has_table_[size_t(b)] ? kDefensive : Float(1);
  return c * cosine_hemisphere_pdf(wi.z) + (1 - c) * tabulated_pdf(wo, wi);
}

Vec3 MeasuredData::sample(const Vec3& wo, Float u_lobe, Float u1, Float u2) const {
  constexpr int kNodesP = kPhiCells + 1;
  const int b = theta_o_bin(wo, kThetaOBins);
  const Float c = has_table_[size_t(b)] ? kDefensive : Float(1);
  if (u_lobe < c) return square_to_cosine_hemisphere(u1, u2);
  const Float u_mirror = (u_lobe - c) / (1 - c);
  // The cell, from the discrete distribution of the patches' masses; the remainders of u1
  // and u2 place the point within it.
  const float* marginal = &marginal_cdf_[size_t(b) * (kThetaCells + 1)];
  const int it = find_interval(marginal, kThetaCells, u1);
  const Float m0 = marginal[it], m1 = marginal[it + 1];
  const Float v1 = m1 > m0 ? std::clamp((u1 - m0) / (m1 - m0), Float(0), kOneMinusEpsilon) : Float(0.5);
  const float* cond = &conditional_cdf_[(size_t(b) * kThetaCells + size_t(it)) * (kPhiCells + 1)];
  const int ip = find_interval(cond, kPhiCells, u2);
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
  Float rel = (Float(ip) + tp) * Float(kPiD / kPhiCells);
  if (u_mirror < Float(0.5)) rel = -rel;
  const MirrorFrame fr = mirror_frame(wo);
  return normalize(ct * fr.wr + (st * std::cos(rel)) * fr.xp + (st * std::sin(rel)) * fr.yp);
}

// --- loading -----------------------------------------------------------------------

std::shared_ptr<const MeasuredData> load_measured(const std::string& path) {
  // Keyed by the canonical path, its size and modification time: a file rewritten in
  // place is read again.
  static std::mutex mutex;
  static std::map<std::string, std::weak_ptr<const MeasuredData>> cache;
  std::error_code ec;
  const std::filesystem::path canonical = std::filesystem::weakly_canonical(path, ec);
  std::string key = ec ? path : canonical.string();
  const auto mtime = std::filesystem::last_write_time(path, ec);
  if (!ec) {
    key.push_back('|');
    key.append(std::to_string(mtime.time_since_epoch().count()));
  }
  {
    const std::lock_guard<std::mutex> lock(mutex);
    if (auto it = cache.find(key); it != cache.end())
      if (auto data = it->second.lock()) return data;
  }
  auto data = std::make_shared<const MeasuredData>(read_merl(path), path);
  const std::lock_guard<std::mutex> lock(mutex);
  cache[key] = data;
  return data;
}

}  // namespace gonio
