// The directional albedo E(μ, α) of gltf_pbr's Charlie sheen lobe (include/gonio/bxdf/gltf_pbr.h),
// which KHR_materials_sheen's albedo scaling reads ("Albedo-scaling technique": "E(x) can be
// looked up in a table"). The table is made here, once, by quadrature of the lobe itself
// (the same charlie_brdf the model evaluates), rather than copied from elsewhere.

#include <algorithm>
#include <array>
#include <cmath>

#include "gonio/bxdf/gltf_pbr.h"

namespace gonio::gltf_pbr {
namespace sheen_table {  // named: unique in a unity batch

constexpr int kMu = 24, kAlpha = 16;       // the table's nodes in μ and α
constexpr int kTheta = 48, kPhi = 32;      // the quadrature's (midpoint rule in cos θi and φ)
constexpr double kMuFirst = 1e-3;          // μ = 0 itself is singular in V; its limit is read at 1e-3

double node_mu(int i) { return std::max(kMuFirst, double(i) / (kMu - 1)); }
double node_alpha(int j) { return kMinSheenAlpha + (1 - kMinSheenAlpha) * double(j) / (kAlpha - 1); }

double quadrature(double mu, double alpha) {
  const double so = std::sqrt(std::max(0.0, 1 - mu * mu));
  double sum = 0;
  for (int t = 0; t < kTheta; ++t) {
    const double ci = (t + 0.5) / kTheta, si = std::sqrt(std::max(0.0, 1 - ci * ci));
    for (int p = 0; p < kPhi; ++p) {
      const double phi = kPi * (p + 0.5) / kPhi;  // symmetric in φ: [0, π] twice
      const double hx = so + si * std::cos(phi), hy = si * std::sin(phi), hz = mu + ci;
      const double cos_h = hz / std::sqrt(hx * hx + hy * hy + hz * hz);
      sum += double(charlie_brdf(Float(mu), Float(ci), Float(cos_h), Float(alpha))) * ci;
    }
  }
  return sum * (2 * kPi / kPhi) / kTheta;  // dω = d(cos θ) dφ
}

struct Table {
  std::array<float, kMu * kAlpha> e{};
  Table() {
    for (int j = 0; j < kAlpha; ++j)
      for (int i = 0; i < kMu; ++i) e[size_t(j * kMu + i)] = float(quadrature(node_mu(i), node_alpha(j)));
  }
};

}  // namespace sheen_table

Float charlie_albedo(Float mu, Float alpha) {
  using namespace sheen_table;
  static const Table table;
  const double x = std::clamp(double(mu), 0.0, 1.0) * (kMu - 1);
  const double y = std::clamp((double(alpha) - kMinSheenAlpha) / (1 - kMinSheenAlpha), 0.0, 1.0) * (kAlpha - 1);
  const int i = std::min(int(x), kMu - 2), j = std::min(int(y), kAlpha - 2);
  const double fx = x - i, fy = y - j;
  const auto at = [&](int a, int b) { return double(table.e[size_t(b * kMu + a)]); };
  const double v = (at(i, j) * (1 - fx) + at(i + 1, j) * fx) * (1 - fy) + (at(i, j + 1) * (1 - fx) + at(i + 1, j + 1) * fx) * fy;
  return Float(std::clamp(v, 0.0, 1.0));
}

}  // namespace gonio::gltf_pbr
