#pragma once
// A colour parameter of SPEC §2 as a Spectrum (the material and scene parsers reduce it to
// RGB with spectrum_to_rgb.h). Accepted forms:
//   number, [r, g, b]                 reflectance: in [0, 1] (RGB upsampled, Jakob & Hanika)
//                                     emission: ≥ 0 (RGB illuminant: m S(rgb/m) D65)
//                                     index: a number > 0 (no RGB)
//   {"spectrum": [[nm, value], ...]}  piecewise linear (any use)
//   {"spectrum": "file.csv"}          two-column CSV, relative to base_dir (any use)
//   {"blackbody": kelvin}             emission only, luminance 1
//   {"illuminant": "D65"}             emission only, luminance 1
//   {"sellmeier": {"B": [..], "C": [..]}}, "BK7" (a named glass)   index only
// Errors are InputErrors that start with the field's name.

#include <string>
#include <string_view>

#include <nlohmann/json.hpp>

#include "gonio/spectrum/spectrum.h"

namespace gonio {

enum class SpectrumUse { kReflectance, kEmission, kIndex };

Spectrum parse_spectrum(const nlohmann::json& value, std::string_view field, SpectrumUse use,
                        const std::string& base_dir = "");

}  // namespace gonio
