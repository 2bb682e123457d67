#pragma once
// Named metals: complex refractive index n + i k relative to vacuum for the RGB channels.

#include <optional>
#include <string_view>
#include <vector>

#include "gonio/color.h"

namespace gonio {

struct ComplexIor {
  Color eta;
  Color k;
};

// In RGB mode the channels' normal-incidence reflectance F0 = ((n−1)² + k²)/((n+1)² + k²)
// is the linear-sRGB colour (D65, CIE 1931 2°, clamped to [0, 1], at most 0.999) of the
// measured reflectance spectrum F0(n(λ), k(λ)) in data/metals/ (the measurements
// tabulated in pbrt-v4's named spectra, linear between rows). Each channel's n is the
// measured n at 650 nm (r), 550 nm (g), 450 nm (b); k = √(((n+1)² R − (n−1)²)/(1 − R)) for
// the channel's colour R, or, where that radicand is negative, k = 0 and n solves
// ((n−1)/(n+1))² = R on the same side of 1 as the measured n. Computed at build time by
// tools/make_metal_table.cpp (whose header gives the quadrature). Returns nothing for an
// unknown name.
std::optional<ComplexIor> named_metal(std::string_view name);

// The names named_metal() knows, for error messages and --help.
const std::vector<std::string_view>& named_metal_names();

}  // namespace gonio
