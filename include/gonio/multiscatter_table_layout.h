#pragma once
// Layout of the microfacet albedo tables (shared by the build-time generator and the
// lookups): rows by roughness, nodes r = sqrt(α) uniform on [0, 1] (finer where the
// albedo changes fastest), columns by μ = cos θ uniform on [0, 1].

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
// arriving from outside onto relative index η ≥ 1, isotropic α.
//   rows by α ∈ [1e-4, 10], uniform in x = √α / (1 + √α) (fine at small α, which is where
//     E changes fastest, and reaching the largest α the materials accept);
//   η nodes uniform in z = ((η − 1)/(η + 1))^(1/2) on [0, 1], η from 1 to ∞ (the last
//     node is F = 1);
//   μ nodes μ = s², s uniform on [0, 1]: dense towards grazing, where E rises steeply.
inline constexpr int kCoatRoughnessSize = 40;
inline constexpr int kCoatEtaSize = 24;
inline constexpr int kCoatCosineSize = 65;
inline constexpr double kCoatMaxAlpha = 10;

inline constexpr double kCoatXMax = 0.75976310729378174;  // √10 / (1 + √10)
// √α at row a.
constexpr double coat_table_sqrt_alpha(int a) {
  const double x = kCoatXMax * double(a) / (kCoatRoughnessSize - 1);
  const double r = x / (1 - x);
  return r < 1e-2 ? 1e-2 : r;
}
// z at η node k (z = 1: η = ∞, total reflection).
constexpr double coat_table_z(int k) { return double(k) / (kCoatEtaSize - 1); }
// μ at column m; column 0 stands for grazing, evaluated just above it.
constexpr double coat_table_mu(int m) {
  const double s = double(m) / (kCoatCosineSize - 1);
  return s * s < 1e-6 ? 1e-6 : s * s;
}
// The node's μ for interpolation (column 0 at μ = 0).
constexpr double coat_table_mu_node(int m) {
  const double s = double(m) / (kCoatCosineSize - 1);
  return s * s;
}

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
