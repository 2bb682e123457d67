#pragma once
// Layout of the RGB → spectrum coefficient table (Jakob & Hanika 2019, §4), shared by its
// build-time generator (tools/make_spectral_tables.cpp) and the run-time lookup.
//
// For an RGB triple whose largest component is number l, the table is indexed by
//   z = rgb[l] (the brightness), x = rgb[(l+1) % 3] / z, y = rgb[(l+2) % 3] / z,
// each in [0, 1]. x and y are sampled uniformly; z on nodes that are denser towards 0
// and 1, z_k = s(s(k / (R − 1))) with the smoothstep s(t) = t² (3 − 2t), where the
// coefficients change fastest (the sigmoid saturates).
//
// Each entry holds (c0, c1, c2) of S(λ) = σ(c0 t² + c1 t + c2) in the normalised
// wavelength t = (λ − 360 nm) / 470 nm ∈ [0, 1] (better conditioned in float than λ in
// nm), σ(x) = 1/2 + x / (2 √(1 + x²)) (Jakob & Hanika 2019, eq. 3).

namespace gonio::rgb_table {

// 48: the round trip over a 16³ grid of the sRGB cube stays within 1.3e-3 (32: 2.9e-3,
// 64: 0.7e-3); the fit takes ~4 s of CPU (docs/spectral.md).
inline constexpr int kRes = 48;

constexpr double smoothstep(double t) { return t * t * (3 - 2 * t); }
// The k-th z node.
constexpr double z_node(int k) { return smoothstep(smoothstep(double(k) / (kRes - 1))); }

// t of a wavelength in nm.
inline constexpr double kT0 = 360.0, kTSpan = 470.0;

}  // namespace gonio::rgb_table
