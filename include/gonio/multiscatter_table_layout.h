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

}  // namespace gonio::tables
