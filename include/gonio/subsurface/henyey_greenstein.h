#pragma once
// The Henyey–Greenstein phase function (Henyey & Greenstein 1941, "Diffuse radiation in
// the Galaxy", ApJ 93, eq. 3): p(μ) = (1 − g²) / (4π (1 + g² − 2gμ)^{3/2}), μ the cosine
// between the direction of travel before and after scattering, g its mean. Here μ is
// measured against the direction of propagation (g > 0 scatters forward), not against
// the reversed direction PBR uses for wo.

#include <algorithm>
#include <cmath>

#include "gonio/math/constants.h"
#include "gonio/math/frame.h"
#include "gonio/math/vec3.h"

namespace gonio {

// Below this |g| the phase function is sampled as isotropic: the inversion below divides
// by 2g and loses every digit as g → 0 (at |g| = 1e-3 the two differ by < 0.3 % in pdf).
inline constexpr Float kHgIsotropicBelow = 1e-3f;

// p(μ) per steradian.
inline Float hg_phase(Float cos_theta, Float g) {
  const Float denom = 1 + g * g - 2 * g * cos_theta;
  return kInv4Pi * (1 - g * g) / (denom * std::sqrt(std::max(denom, Float(1e-12))));
}

// μ from ξ in [0, 1) by inverting the CDF F(μ) = (1 − g²)/(2g) [(1 + g² − 2gμ)^{-1/2} −
// (1 + g)^{-1}] (PBR 3rd ed., eq. 15.7, written for the direction of travel):
// μ = (1 + g² − ((1 − g²) / (1 − g + 2gξ))²) / (2g). ξ = 0 gives −1, ξ → 1 gives 1.
inline Float hg_sample_cos(Float xi, Float g) {
  if (std::abs(g) < kHgIsotropicBelow) return std::clamp(1 - 2 * xi, Float(-1), Float(1));
  const Float s = (1 - g * g) / (1 - g + 2 * g * xi);
  return std::clamp((1 + g * g - s * s) / (2 * g), Float(-1), Float(1));
}

// A new direction of travel after scattering from direction d (unit), with μ = cos
// between them drawn from HG and the azimuth uniform. Its pdf is hg_phase(μ, g).
inline Vec3 hg_sample(const Vec3& d, Float g, Float u1, Float u2) {
  const Float mu = hg_sample_cos(u1, g);
  const Float sin_t = std::sqrt(std::max(Float(0), 1 - mu * mu));
  const Float phi = 2 * kPi * u2;
  const Frame f = Frame::from_normal(d);
  return normalize(f.to_world({sin_t * std::cos(phi), sin_t * std::sin(phi), mu}));
}

}  // namespace gonio
