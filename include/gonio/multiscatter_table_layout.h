#pragma once

// Layout of the microfacet albedo tables (shared by the build-time generator and the
// lookups): rows by roughness, nodes r = sqrt(α) uniform on [0, 1] (finer where the
// albedo changes fastest), columns by μ = cos θ uniform on [0, 1].

#include <cmath>

namespace gonio::tables {

inline constexpr int kAlbedoRoughnessSize = 32;
inline constexpr int kAlbedoCosineSize = 65;  // even number of intervals, for Simpson

// α at row a; row 0 is a nearly smooth surface (E = 1 to float precision).
constexpr double albedo_table_alpha(int a) {
  const double r = double(a) / (kAlbedoRoughnessSize - 1);
  return r * r < 1e-4 ? 1e-4 : r * r;
}
// μ at column m; column 0 stands for grazing, evaluated just above it.
constexpr double albedo_table_mu(int m) {
  const double mu = double(m) / (kAlbedoCosineSize - 1);
  return mu < 1e-4 ? 1e-4 : mu;
}

extern const float kGgxAlbedo[kAlbedoRoughnessSize][kAlbedoCosineSize];
extern const float kGgxAverageAlbedo[kAlbedoRoughnessSize];
extern const float kBeckmannAlbedo[kAlbedoRoughnessSize][kAlbedoCosineSize];
extern const float kBeckmannAverageAlbedo[kAlbedoRoughnessSize];

// Sampling tables of the lobes shaped like (1 − E(μ)) μ: the Kulla–Conty compensation lobe
// (multiscatter.h) and the base under a rough plastic coat (coat_albedo.h). Per row (and
// per η node for the coat), from the values as stored (float) and their linear
// interpolant in μ:
//   Cdf[m]  = ∫₀^μm (1 − E) μ dμ / ∫₀¹ (1 − E) μ dμ  (0 at m = 0, 1 at the last node);
//   Loss    = 2 ∫₀¹ (1 − E) μ dμ = 1 − Ē, kept apart from Ē so that it keeps its relative
//             precision where Ē → 1 (a near-smooth surface, a coat of index 10⁴).
using AlbedoCdfTable = float[kAlbedoRoughnessSize][kAlbedoCosineSize];
using AlbedoLossTable = float[kAlbedoRoughnessSize];
extern const AlbedoCdfTable kGgxAlbedoCdf, kBeckmannAlbedoCdf;
extern const AlbedoLossTable kGgxAlbedoLoss, kBeckmannAlbedoLoss;

// Rough dielectric albedo tables E(μ, α, η'): R + T of the single-scattering rough
// dielectric in importance mode, for wo on the side of the lower index ("enter", light
// going into the denser medium) and of the higher one ("exit"), with η' ≥ 1 the ratio of
// the two indices. Rows by α as above; η' nodes uniform in z = sqrt((η'−1)/(η'+1)) on
// [0, sqrt(3/5)] (η' from 1 to 4, denser near 1 where E changes fastest); μ uniform.
inline constexpr int kDielectricEtaSize = 16;
inline constexpr int kDielectricCosineSize = 65;
inline constexpr double kDielectricZMax = 0.7745966692414834;  // sqrt(3/5): η' = 4

constexpr double dielectric_table_eta(int k) {
  const double z = kDielectricZMax * double(k) / (kDielectricEtaSize - 1);
  return (1 + z * z) / (1 - z * z);
}
constexpr double dielectric_table_mu(int m) {
  const double mu = double(m) / (kDielectricCosineSize - 1);
  return mu < 1e-4 ? 1e-4 : mu;
}

// [side: 0 enter, 1 exit][α row][η' node][μ]
using DielectricAlbedoTable = float[2][kAlbedoRoughnessSize][kDielectricEtaSize][kDielectricCosineSize];
// Cosine-weighted means 2 ∫ E μ dμ of the piecewise-linear interpolant in μ, so that the
// compensation lobe integrates exactly to what the table says is missing.
using DielectricAverageTable = float[2][kAlbedoRoughnessSize][kDielectricEtaSize];
extern const DielectricAlbedoTable kGgxDielectricAlbedo, kBeckmannDielectricAlbedo;
extern const DielectricAverageTable kGgxDielectricAverage, kBeckmannDielectricAverage;

// Rough dielectric coat (plastic) albedo E_coat(μ, α, η): the reflection alone (no
// transmission) of the single-scattering microfacet BRDF with dielectric Fresnel, light
// arriving from outside onto relative index η ≥ 1, isotropic α. Near grazing E_coat
// changes on the scale μ ~ α (masking) and, for η near 1, on the scale μ ~ z (Fresnel
// rises towards 1 only where cos θt = √(μ² + 4z²) is small), so the nodes are dense there
// (issue 9: linear in √α, z and √μ they left the white furnace 2.5% off at α = 1e-3,
// 89.94°, and 3% for η < 1.001):
//   rows by α log-uniform on [1e-3, 10] (below 1e-3 the coat is smooth: kSmoothAlpha);
//   η nodes in z = ((η − 1)/(η + 1))^(1/2) ∈ [0, 1]: 0; 25 geometric (ratio 1.3) from
//     2^-12 (the z of the float next to 1) towards 0.16; uniform in steps of 0.04 from
//     0.16 to 0.80; geometric in w = 1 − z (ratio 1.30) from w = 0.16 to w = 10⁻⁴
//     (η ≈ 2·10⁴), where E_coat changes on the scale of Brewster's angle, c ~ 1/η ~ w;
//     z = 1 (η = ∞: F = 1);
//   μ nodes μ = s⁴, s uniform on [0, 1].
inline constexpr int kCoatRoughnessSize = 48;
inline constexpr int kCoatNearOneEtaNodes = 25;
inline constexpr int kCoatUniformEtaNodes = 17;  // 0.16, 0.20, ..., 0.80
inline constexpr int kCoatLargeEtaNodes = 29;    // w = 0.16 ... 1e-4
inline constexpr int kCoatEtaSize = 1 + kCoatNearOneEtaNodes + kCoatUniformEtaNodes + kCoatLargeEtaNodes + 1;
inline constexpr int kCoatCosineSize = 81;
inline constexpr double kCoatMinAlpha = 1e-3;
inline constexpr double kCoatMaxAlpha = 10;
// ln(kCoatMaxAlpha / kCoatMinAlpha), a constant so that lookups need no static
// initialisation (the table generator checks it against std::log at every build).
inline constexpr double kCoatLogAlphaRange = 9.2103403719761836;
inline constexpr double kCoatMinZ = 1.0 / 4096;
inline constexpr double kCoatUniformZ = 0.16;  // the first uniform node
inline constexpr double kCoatZStep = 0.04;
inline constexpr double kCoatLargeEtaW = 0.16;  // w = 1 − z of the first large-η node
inline constexpr double kCoatMinW = 1e-4;

// α at row a.
inline double coat_table_alpha(int a) {
  return kCoatMinAlpha * std::pow(kCoatMaxAlpha / kCoatMinAlpha, double(a) / (kCoatRoughnessSize - 1));
}
// z at η node k.
inline double coat_table_z(int k) {
  if (k <= 0) return 0;
  if (k <= kCoatNearOneEtaNodes)
    return kCoatMinZ * std::pow(kCoatUniformZ / kCoatMinZ, double(k - 1) / kCoatNearOneEtaNodes);
  k -= kCoatNearOneEtaNodes + 1;
  if (k < kCoatUniformEtaNodes) return kCoatUniformZ + kCoatZStep * k;
  k -= kCoatUniformEtaNodes;
  if (k < kCoatLargeEtaNodes)
    return 1 - kCoatLargeEtaW * std::pow(kCoatMinW / kCoatLargeEtaW, double(k) / (kCoatLargeEtaNodes - 1));
  return 1;
}
// The node index k ≤ kCoatEtaSize − 2 with z(k) ≤ z < z(k + 1) (bisection: only
// CoatAlbedo::make calls it, once per material).
inline int coat_table_node_below(double z) {
  int lo = 0, hi = kCoatEtaSize - 1;
  while (hi - lo > 1) {
    const int mid = (lo + hi) / 2;
    if (coat_table_z(mid) <= z) lo = mid;
    else hi = mid;
  }
  return lo;
}
// The node's μ for interpolation (column 0 at μ = 0).
constexpr double coat_table_mu_node(int m) {
  const double s = double(m) / (kCoatCosineSize - 1);
  return (s * s) * (s * s);
}
// μ at column m; column 0 stands for grazing, evaluated just above it.
constexpr double coat_table_mu(int m) { return m == 0 ? 1e-10 : coat_table_mu_node(m); }
// The nodes' μ and the reciprocal widths of the intervals above them, in float, for
// lookups without double arithmetic or a division (CoatAlbedo::E_at_row).
struct CoatMuNodes {
  float mu[kCoatCosineSize];
  float inv_width[kCoatCosineSize];  // 1 / (μ_{m+1} − μ_m); the last one unused
};
constexpr CoatMuNodes make_coat_mu_nodes() {
  CoatMuNodes n{};
  for (int m = 0; m < kCoatCosineSize; ++m) n.mu[m] = float(coat_table_mu_node(m));
  for (int m = 0; m + 1 < kCoatCosineSize; ++m) n.inv_width[m] = 1.0f / (n.mu[m + 1] - n.mu[m]);
  return n;
}
inline constexpr CoatMuNodes kCoatMuNodes = make_coat_mu_nodes();

using CoatAlbedoTable = float[kCoatRoughnessSize][kCoatEtaSize][kCoatCosineSize];
// 2 ∫ E μ dμ of the piecewise-linear interpolant in μ (exact, hemispherical_average.h).
using CoatAverageTable = float[kCoatRoughnessSize][kCoatEtaSize];
extern const CoatAlbedoTable kGgxCoatAlbedo, kBeckmannCoatAlbedo;
extern const CoatAverageTable kGgxCoatAverage, kBeckmannCoatAverage;
// The coat's sampling tables (as for the albedo tables above).
using CoatCdfTable = float[kCoatRoughnessSize][kCoatEtaSize][kCoatCosineSize];
using CoatLossTable = float[kCoatRoughnessSize][kCoatEtaSize];
extern const CoatCdfTable kGgxCoatCdf, kBeckmannCoatCdf;
extern const CoatLossTable kGgxCoatLoss, kBeckmannCoatLoss;

}  // namespace gonio::tables
