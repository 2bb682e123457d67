// Lookups into the build-time albedo tables (multiscatter.h).

#include "gonio/multiscatter.h"

#include <algorithm>
#include <cmath>

#include "gonio/multiscatter_table_layout.h"

namespace gonio {

namespace {
using namespace tables;

// Fractional row for α (rows are uniform in r = sqrt(α)).
Float row_of(Float alpha) {
  const Float r = std::sqrt(std::clamp(alpha, Float(0), Float(1)));
  return r * Float(kAlbedoRoughnessSize - 1);
}
}  // namespace

Float microfacet_albedo(MicrofacetType type, Float alpha, Float mu) {
  const auto& table = type == MicrofacetType::GGX ? kGgxAlbedo : kBeckmannAlbedo;
  const Float fr = row_of(alpha);
  const Float fc = std::clamp(mu, Float(0), Float(1)) * Float(kAlbedoCosineSize - 1);
  const int r0 = std::min(int(fr), kAlbedoRoughnessSize - 2), c0 = std::min(int(fc), kAlbedoCosineSize - 2);
  const Float tr = fr - Float(r0), tc = fc - Float(c0);
  const Float top = table[r0][c0] * (1 - tc) + table[r0][c0 + 1] * tc;
  const Float bottom = table[r0 + 1][c0] * (1 - tc) + table[r0 + 1][c0 + 1] * tc;
  return top * (1 - tr) + bottom * tr;
}

// --- sampling μ ∝ (1 − E(μ)) μ --------------------------------------------------------
//
// E is the linear interpolant of a table row at nodes μ_m, so on a node interval [a, b]
// the density is ∝ (A + (B − A) v)(a + h v), h = b − a, μ = a + h v, with A, B the row's
// 1 − E at the ends: its integral over [a, a + h v] is the cubic
//   P(v) = h (A a v + (A h + (B − A) a) v²/2 + (B − A) h v³/3),
// increasing on [0, 1]. The interval is found in the row's CDF (built by
// tools/make_albedo_tables.cpp from the same stored values), and P(v) = t P(1) is solved
// by Newton's method kept inside a bisection bracket.

namespace {

double solve_complement_interval(double a, double h, double A, double B, double t) {
  const double d = B - A;
  const double c1 = h * A * a, c2 = h * (A * h + d * a) / 2, c3 = h * d * h / 3;
  const double target = t * (c1 + c2 + c3);
  double lo = 0, hi = 1;
  // Start from the root of the quadratic part (exact where 1 − E is constant on the interval).
  double v = c2 > 0 ? (-c1 + std::sqrt(c1 * c1 + 4 * c2 * target)) / (2 * c2) : t;
  v = std::clamp(v, 0.0, 1.0);
  for (int it = 0; it < 24; ++it) {
    const double p = ((c3 * v + c2) * v + c1) * v - target;
    if (p > 0) hi = v;
    else lo = v;
    const double dp = (3 * c3 * v + 2 * c2) * v + c1;
    double next = dp > 0 ? v - p / dp : (lo + hi) / 2;
    if (!(next > lo && next < hi)) next = (lo + hi) / 2;
    if (std::abs(next - v) <= 1e-9) return next;
    v = next;
  }
  return v;
}

// One row: values e (1 − E clamped at 0), its CDF, nodes node(m), m < n.
template <typename Node>
Float sample_complement_row(const float* e, const float* cdf, int n, Node&& node, Float u) {
  // The interval m with cdf[m] ≤ u < cdf[m + 1] (intervals of zero mass are never chosen).
  int lo = 0, hi = n - 1;
  while (hi - lo > 1) {
    const int mid = (lo + hi) / 2;
    if (cdf[mid] <= u) lo = mid;
    else hi = mid;
  }
  const double c0 = cdf[lo], c1 = cdf[lo + 1];
  const double t = c1 > c0 ? std::clamp((double(u) - c0) / (c1 - c0), 0.0, 1.0) : 0.5;
  const double a = node(lo), b = node(lo + 1);
  const double A = std::max(0.0, 1.0 - double(e[lo])), B = std::max(0.0, 1.0 - double(e[lo + 1]));
  const double v = solve_complement_interval(a, b - a, A, B, t);
  return Float(std::clamp(a + (b - a) * v, 0.0, 1.0));
}

}  // namespace

AlbedoComplementSampler AlbedoComplementSampler::make(MicrofacetType type, Float alpha) {
  const auto& loss = type == MicrofacetType::GGX ? kGgxAlbedoLoss : kBeckmannAlbedoLoss;
  AlbedoComplementSampler s;
  s.type = type;
  const Float fr = row_of(alpha);  // as microfacet_albedo
  s.row = std::min(int(fr), kAlbedoRoughnessSize - 2);
  const Float tr = fr - Float(s.row);
  const Float w0 = (1 - tr) * loss[s.row], w1 = tr * loss[s.row + 1];
  s.loss = w0 + w1;
  s.p_row = s.loss > 0 ? w0 / s.loss : Float(1);
  return s;
}

Float AlbedoComplementSampler::sample(Float u) const {
  const auto& table = type == MicrofacetType::GGX ? kGgxAlbedo : kBeckmannAlbedo;
  const auto& cdf = type == MicrofacetType::GGX ? kGgxAlbedoCdf : kBeckmannAlbedoCdf;
  int r = row;
  if (u < p_row) {
    u = u / p_row;
  } else {
    u = (u - p_row) / (1 - p_row);
    r = row + 1;
  }
  u = std::min(u, kOneMinusEpsilon);
  return sample_complement_row(table[r], cdf[r], kAlbedoCosineSize,
                               [](int m) { return double(m) / (kAlbedoCosineSize - 1); }, u);
}

Float microfacet_average_albedo(MicrofacetType type, Float alpha) {
  const auto& table = type == MicrofacetType::GGX ? kGgxAverageAlbedo : kBeckmannAverageAlbedo;
  const Float fr = row_of(alpha);
  const int r0 = std::min(int(fr), kAlbedoRoughnessSize - 2);
  const Float tr = fr - Float(r0);
  return table[r0] * (1 - tr) + table[r0 + 1] * tr;
}

}  // namespace gonio

// --- rough dielectric ----------------------------------------------------------------

#include "gonio/dielectric_multiscatter.h"
#include "gonio/fresnel.h"
#include "gonio/hemispherical_average.h"

namespace gonio {
namespace {
using namespace tables;

struct DielectricCoords {
  int side;     // 0: wo on the lower index's side, 1: on the higher one
  int r0, k0;   // lower α row and η' node
  Float tr, tk; // their fractions
};

DielectricCoords dielectric_coords(Float alpha, Float e) {
  DielectricCoords c;
  c.side = e >= 1 ? 0 : 1;
  const Float eta = e >= 1 ? e : 1 / e;
  const Float z = std::sqrt(std::max(Float(0), (eta - 1) / (eta + 1)));
  const Float fk = std::min(z / Float(kDielectricZMax), Float(1)) * Float(kDielectricEtaSize - 1);
  const Float fr = row_of(alpha);
  c.r0 = std::min(int(fr), kAlbedoRoughnessSize - 2);
  c.k0 = std::min(int(fk), kDielectricEtaSize - 2);
  c.tr = fr - Float(c.r0);
  c.tk = fk - Float(c.k0);
  return c;
}
}  // namespace

Float dielectric_microfacet_albedo(MicrofacetType type, Float alpha, Float e, Float mu) {
  const auto& table = type == MicrofacetType::GGX ? kGgxDielectricAlbedo : kBeckmannDielectricAlbedo;
  const DielectricCoords c = dielectric_coords(alpha, e);
  const Float fm = std::clamp(mu, Float(0), Float(1)) * Float(kDielectricCosineSize - 1);
  const int m0 = std::min(int(fm), kDielectricCosineSize - 2);
  const Float tm = fm - Float(m0);
  auto at = [&](int r, int k) {
    const float* row = table[c.side][r][k];
    return row[m0] * (1 - tm) + row[m0 + 1] * tm;
  };
  const Float lo = at(c.r0, c.k0) * (1 - c.tk) + at(c.r0, c.k0 + 1) * c.tk;
  const Float hi = at(c.r0 + 1, c.k0) * (1 - c.tk) + at(c.r0 + 1, c.k0 + 1) * c.tk;
  return lo * (1 - c.tr) + hi * c.tr;
}

Float dielectric_microfacet_average_albedo(MicrofacetType type, Float alpha, Float e) {
  const auto& table = type == MicrofacetType::GGX ? kGgxDielectricAverage : kBeckmannDielectricAverage;
  const DielectricCoords c = dielectric_coords(alpha, e);
  const auto& t = table[c.side];
  const Float lo = t[c.r0][c.k0] * (1 - c.tk) + t[c.r0][c.k0 + 1] * c.tk;
  const Float hi = t[c.r0 + 1][c.k0] * (1 - c.tk) + t[c.r0 + 1][c.k0 + 1] * c.tk;
  return lo * (1 - c.tr) + hi * c.tr;
}

Float average_dielectric_fresnel(Float eta) {
  // F has a kink at the critical angle when η < 1, so many panels.
  return Float(cosine_weighted_average([&](double mu) { return fresnel_dielectric(mu, double(eta)); }, 2048));
}

}  // namespace gonio

// --- plastic coat --------------------------------------------------------------------

#include "gonio/coat_albedo.h"

namespace gonio {
namespace {
using namespace tables;

struct CoatRow {
  int r0;
  Float tr;
};
// Rows log-uniform in α (multiscatter_table_layout.h).
constexpr Float kRowsPerLog = Float((kCoatRoughnessSize - 1) / kCoatLogAlphaRange);
CoatRow coat_row(Float alpha) {
  const Float a = std::clamp(alpha, Float(kCoatMinAlpha), Float(kCoatMaxAlpha));
  const Float fx = std::log(a * Float(1 / kCoatMinAlpha)) * kRowsPerLog;
  const int r0 = std::clamp(int(fx), 0, kCoatRoughnessSize - 2);
  return {r0, std::clamp(fx - Float(r0), Float(0), Float(1))};
}

CoatRow coat_row(const CoatAlbedo& c, Float alpha) {
  return alpha == c.row_alpha ? CoatRow{c.r0, c.tr} : coat_row(alpha);
}
}  // namespace

CoatAlbedo CoatAlbedo::make(MicrofacetType type, Float eta) {
  CoatAlbedo c;
  c.type = type;
  const double e = std::max(1.0, double(eta));
  const double z = std::sqrt((e - 1) / (e + 1));
  c.k0 = coat_table_node_below(z);
  const double z0 = coat_table_z(c.k0), z1 = coat_table_z(c.k0 + 1);
  c.tk = Float(std::clamp((z - z0) / (z1 - z0), 0.0, 1.0));  // linear in z between nodes
  return c;
}

void CoatAlbedo::prepare_roughness(Float alpha) {
  const CoatRow r = coat_row(alpha);
  row_alpha = alpha;
  r0 = r.r0;
  tr = r.tr;
}

Float CoatAlbedo::E_any_row(Float alpha, Float mu) const {
  const CoatRow r = coat_row(alpha);
  return E_at_row(r.r0, r.tr, mu);
}

Float CoatAlbedo::average(Float alpha) const {
  const auto& t = type == MicrofacetType::GGX ? kGgxCoatAverage : kBeckmannCoatAverage;
  const CoatRow r = coat_row(*this, alpha);
  const Float lo = t[r.r0][k0] * (1 - tk) + t[r.r0][k0 + 1] * tk;
  const Float hi = t[r.r0 + 1][k0] * (1 - tk) + t[r.r0 + 1][k0 + 1] * tk;
  return lo * (1 - r.tr) + hi * r.tr;
}

namespace {
// The four (α row, η node) rows around (alpha, this η) and their weights in the bilinear
// interpolant, times each row's loss: the mixture weights of the complement's density.
struct CoatMixture {
  int r0, k0;
  Float w[4];  // (r0, k0), (r0, k0 + 1), (r0 + 1, k0), (r0 + 1, k0 + 1)
  Float total;
};
CoatMixture coat_mixture(const CoatAlbedo& c, Float alpha) {
  const MicrofacetType type = c.type;
  const int k0 = c.k0;
  const Float tk = c.tk;
  const auto& loss = type == MicrofacetType::GGX ? kGgxCoatLoss : kBeckmannCoatLoss;
  const CoatRow r = coat_row(c, alpha);
  CoatMixture m{r.r0, k0, {}, 0};
  m.w[0] = (1 - r.tr) * (1 - tk) * loss[r.r0][k0];
  m.w[1] = (1 - r.tr) * tk * loss[r.r0][k0 + 1];
  m.w[2] = r.tr * (1 - tk) * loss[r.r0 + 1][k0];
  m.w[3] = r.tr * tk * loss[r.r0 + 1][k0 + 1];
  m.total = (m.w[0] + m.w[1]) + (m.w[2] + m.w[3]);
  return m;
}
}  // namespace

Float CoatAlbedo::complement_loss(Float alpha) const { return coat_mixture(*this, alpha).total; }

Float CoatAlbedo::sample_complement(Float alpha, Float u) const {
  const auto& table = type == MicrofacetType::GGX ? kGgxCoatAlbedo : kBeckmannCoatAlbedo;
  const auto& cdf = type == MicrofacetType::GGX ? kGgxCoatCdf : kBeckmannCoatCdf;
  const CoatMixture m = coat_mixture(*this, alpha);
  // Choose a row with probability w / total and reuse u within it.
  Float x = u * m.total;
  int j = 0;
  while (j < 3 && !(x < m.w[j])) {
    x -= m.w[j];
    ++j;
  }
  while (!(m.w[j] > 0) && j > 0) --j;  // rounding past the last non-empty row
  const Float v = m.w[j] > 0 ? std::clamp(x / m.w[j], Float(0), kOneMinusEpsilon) : u;
  const int a = m.r0 + (j >> 1), k = m.k0 + (j & 1);
  return sample_complement_row(table[a][k], cdf[a][k], kCoatCosineSize,
                               [](int i) { return coat_table_mu_node(i); }, v);
}

namespace {
// α(φ)² = αx² cos²φ + αy² sin²φ for the azimuth of w (Heitz 2014, eq. 86); at normal
// incidence, where φ is undefined, the mean of the two.
Float projected_alpha(const MicrofacetDistribution& d, const Vec3& w) {
  const Float s2 = w.x * w.x + w.y * w.y;
  if (!(s2 > 0)) return std::sqrt((d.alpha_x * d.alpha_x + d.alpha_y * d.alpha_y) / 2);
  return std::sqrt((w.x * w.x * d.alpha_x * d.alpha_x + w.y * w.y * d.alpha_y * d.alpha_y) / s2);
}
}  // namespace

Float CoatAlbedo::E_anisotropic(const MicrofacetDistribution& d, const Vec3& w) const {
  return E(projected_alpha(d, w), std::abs(w.z));
}

Float CoatAlbedo::average(const MicrofacetDistribution& d) const {
  if (d.is_isotropic()) return average(d.alpha_x);
  // (1/2π) ∫ Ē(α(φ)) dφ, the midpoint rule over a quarter turn (α(φ) has its symmetry).
  constexpr int n = 32;
  double acc = 0;
  for (int i = 0; i < n; ++i) {
    const double phi = (i + 0.5) / n * (kPiD / 2);
    acc += average(projected_alpha(d, {Float(std::cos(phi)), Float(std::sin(phi)), 0}));
  }
  return Float(acc / n);
}

}  // namespace gonio
