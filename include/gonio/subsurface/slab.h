#pragma once
// `gonio subsurface` (SPEC §3): a semi-infinite slab of a `subsurface` material (surface
// z = 0, medium below) lit by a collimated beam at normal incidence at the origin. The
// result is the same for both methods: the random walk estimates it (slab_random_walk),
// the diffusion profile computes it (diffusion.h).

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <vector>

#include "gonio/color.h"
#include "gonio/subsurface/medium.h"

namespace gonio {

struct SlabProfilePoint {
  Float r = 0;   // distance from the point of incidence, scene units
  Color value;   // exitant power per unit area at r, per unit incident power
};

struct SlabResult {
  Color Rd{0};      // total diffuse reflectance (relative to the incident power)
  Color stderr_{0}; // its standard error (0 for a closed form)
  std::vector<SlabProfilePoint> profile;
};

// The radii at which the profile is reported: kSlabProfilePoints values log-spaced from
// 0.01 to 20 transport mean free paths ℓ = 1 / (σa + (1 − g) σs) of the channel that
// reaches farthest (the largest ℓ; 1 scene unit if no channel attenuates). A Monte Carlo
// estimate gives the mean over the annulus [r / √q, r √q], q the ratio of neighbours.
inline constexpr int kSlabProfilePoints = 40;
inline std::vector<Float> slab_profile_radii(const Medium& m) {
  Float ell = 0;
  for (int c = 0; c < Color::size(); ++c) {
    const Float st = m.sigma_a[c] + (1 - m.g) * m.sigma_s[c];
    if (st > 0) ell = std::max(ell, 1 / st);
  }
  if (!(ell > 0) || !std::isfinite(ell)) ell = 1;
  std::vector<Float> r(kSlabProfilePoints);
  for (int k = 0; k < kSlabProfilePoints; ++k)
    r[static_cast<size_t>(k)] = ell * std::pow(Float(10), Float(-2) + std::log10(Float(2000)) * Float(k) / (kSlabProfilePoints - 1));
  return r;
}

}  // namespace gonio
