#pragma once
// The volume inside an `openpbr` material's shape when it transmits (issue 35, stage 2):
// what `gonio render` fills the shape with. The BSDF (bxdf/openpbr.h) describes the
// surface only; with `transmission_depth` > 0 the colour of transmitted light comes from
// this medium instead of a tint at the surface.
//
// SPEC-OPB (OpenPBR Surface 1.1), "Translucent base": transmission_color C is the colour
// light takes after travelling transmission_depth d through the medium, so the extinction
// is μt = −ln(C)/d per channel; transmission_scatter S gives the scattering coefficient
// μs = S/d, and the absorption is what remains, μa = μt − μs; where that is negative in a
// channel, every channel's μa is raised by the same amount until the smallest is 0 (the
// spec's shift, which keeps the hue of the absorption and μs as given), and μt = μa + μs.
// transmission_scatter_anisotropy is the Henyey–Greenstein g.

#include <algorithm>
#include <cmath>
#include <optional>

#include "gonio/bxdf/openpbr.h"
#include "gonio/subsurface/medium.h"

namespace gonio::openpbr {

// The smallest transmission_color the extinction is computed from: C = 0 would give an
// infinite μt. e^−13.8 is as black as a float image can tell over the depth.
inline constexpr Float kMinTransmissionColor = Float(1e-6);

// −ln(C)/d for one channel, C clamped to [kMinTransmissionColor, 1].
inline Float extinction_from_colour(Float c, Float depth) {
  return -std::log(std::clamp(c, kMinTransmissionColor, Float(1))) / depth;
}

// The interior of a shape whose openpbr material transmits into a medium: nullopt when
// there is none (no transmission, thin-walled, or transmission_depth 0, where
// transmission_color is a tint at the surface). U: Color (the renderer's RGB media).
template <typename U>
std::optional<MediumT<U>> transmission_medium(const OpenPbrParams<U>& p) {
  if (!(p.transmission_weight > 0) || p.geometry_thin_walled || !(p.transmission_depth > 0)) return std::nullopt;
  constexpr int N = U::size();
  MediumT<U> m;
  Float lowest = 0;
  for (int c = 0; c < N; ++c) {
    const Float mu_t = extinction_from_colour(p.transmission_color[c], p.transmission_depth);
    m.sigma_s[c] = std::max(p.transmission_scatter[c], Float(0)) / p.transmission_depth;
    m.sigma_a[c] = mu_t - m.sigma_s[c];
    lowest = std::min(lowest, m.sigma_a[c]);
  }
  for (int c = 0; c < N; ++c) m.sigma_a[c] -= lowest;  // the spec's shift (lowest ≤ 0)
  m.g = std::clamp(p.transmission_scatter_anisotropy, Float(-0.99), Float(0.99));
  return m;
}

}  // namespace gonio::openpbr
