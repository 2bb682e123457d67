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

// In RGB mode the channels (r, g, b) take the measured index at 650, 550 and 450 nm,
// linearly interpolated in the tables of data/metals/ (which reproduce the measurements
// tabulated in pbrt-v4's named spectra) by tools/make_metal_table.cpp at build time.
// Returns nothing for an unknown name.
std::optional<ComplexIor> named_metal(std::string_view name);

// The names named_metal() knows, for error messages and --help.
const std::vector<std::string_view>& named_metal_names();

}  // namespace gonio
