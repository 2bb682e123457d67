#pragma once
// A homogeneous participating medium (issue 14): the inside of a `subsurface` material.
// Coefficients are per colour channel (RGB, or the wavelengths of a spectral path) in
// 1 / scene unit; scattering follows the Henyey–Greenstein phase function with
// asymmetry g (Henyey & Greenstein 1941), g = 0 being isotropic.

#include "gonio/color.h"

namespace gonio {

template <typename C>
struct MediumT {
  C sigma_s{0};  // scattering coefficient
  C sigma_a{0};  // absorption coefficient
  Float g = 0;   // mean cosine of the phase function, in (-1, 1)

  C sigma_t() const { return sigma_s + sigma_a; }
  // Single-scattering albedo ϖ = σs / σt per channel (0 where σt = 0).
  C single_scattering_albedo() const {
    C a = sigma_s;
    a /= sigma_t();  // BasicColor's division gives 0 where the divisor is 0
    return a;
  }
};
using Medium = MediumT<Color>;

}  // namespace gonio
