#pragma once
// RGB mode's reduction of a spectrum (SPEC §2: "in RGB mode a spectrum is reduced to RGB"),
// by the use the spectrum has:
//   reflectance: the linear-sRGB colour of the surface under D65, the white of sRGB
//     (XYZ = ∫ ρ(λ) D65(λ) x̄ȳz̄(λ) dλ / ∫ D65 ȳ dλ, CIE 15:2004 §7.1; IEC 61966-2-1
//     matrix), so ρ = 1 gives (1, 1, 1); outside the sRGB gamut clamped to [0, 1];
//   emission: the linear-sRGB of the radiance spectrum, normalised as the spectral mode's
//     lights (Y = ∫ L ȳ dλ / ∫ ȳ dλ: D65 of luminance v gives (v, v, v)), negatives clamped
//     to 0;
//   index (n or k): the values at 650, 550 and 450 nm, the wavelengths at which RGB mode
//     takes the named metals' n (their k is fitted to their colour: gonio/metals.h).

#include "gonio/color.h"
#include "gonio/spectrum/spectrum.h"
#include "gonio/spectrum/spectrum_json.h"

namespace gonio {

// The wavelengths that stand for the red, green and blue channels of an index.
inline constexpr Float kRgbIndexWavelengths[3] = {650, 550, 450};

Color spectrum_to_rgb(const Spectrum& s, SpectrumUse use);

}  // namespace gonio
