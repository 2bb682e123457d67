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
  // 2 ∫ F(μ) μ dμ by Simpson's rule in double; F has a kink at the critical angle when
  // η < 1, so many intervals.
  constexpr int n = 2048;
  double acc = 0;
  for (int i = 0; i <= n; ++i) {
    const double mu = double(i) / n;
    const double w = (i == 0 || i == n) ? 1 : (i % 2 ? 4 : 2);
    acc += w * 2 * mu * fresnel_dielectric(mu, double(eta));
  }
  return Float(acc / (3.0 * n));
}

}  // namespace gonio
