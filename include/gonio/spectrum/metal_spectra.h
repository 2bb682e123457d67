#pragma once
// The named metals' complex refractive index n(λ) + i k(λ) (SPEC §2 `"material": "Au"`),
// as measured in data/metals/, interpolated linearly between the tabulated wavelengths:
// what spectral mode evaluates at a path's wavelengths. (RGB mode's per-channel constants
// are metals.h.)

#include <optional>
#include <string_view>

#include "gonio/spectrum/piecewise_linear.h"

namespace gonio {

struct MetalSpectra {
  PiecewiseLinearSpectrum eta, k;
};

// Nothing for an unknown name (case-sensitive; the names of named_metal_names()).
std::optional<MetalSpectra> named_metal_spectra(std::string_view name);

}  // namespace gonio
