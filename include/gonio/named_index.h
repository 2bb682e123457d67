#pragma once
// The refractive index of a named metal or glass per colour channel, and the range of a
// numeric one: what `gonio fresnel --material/--eta/--k` and the Python module's
// gonio.fresnel() accept, with the same messages.

#include <optional>
#include <string_view>
#include <utility>
#include <vector>

#include "gonio/math/constants.h"

namespace gonio {

// (eta, k) relative to vacuum per channel. Without a wavelength, the RGB-mode index
// (3 channels): a metal's named_metal() (metals.h), a glass's at kRgbIndexWavelengths
// (650, 550, 450 nm). At wavelength `nm`: one channel, the measured index there, linear
// between the rows of data/metals/ and data/glasses/. Throws InputError
// `--material: unknown material "X" (known: Au, ..., BK7, ...)` for any other name.
std::vector<std::pair<double, double>> named_index(std::string_view name, std::optional<Float> nm = std::nullopt);

// Throws InputError "--eta must be in [0.0001, 10000], got X" or "--k must be in [0, 10000],
// got X" unless eta ∈ [10⁻⁴, 10⁴] and k ∈ [0, 10⁴] (the material descriptions' ranges).
void check_fresnel_index(double eta, double k);

}  // namespace gonio
