#pragma once
// Named glasses (`"eta": "BK7"`, SPEC §2): the refractive index of the Schott glasses in
// data/glasses/, interpolated linearly between the tabulated wavelengths.

#include <optional>
#include <string_view>
#include <vector>

#include "gonio/spectrum/piecewise_linear.h"

namespace gonio {

// The index of the named glass, or nothing for an unknown name (case-sensitive).
std::optional<PiecewiseLinearSpectrum> named_glass(std::string_view name);
// The names named_glass() knows: BAF10, BK7, FK51A, LASF9, SF10, SF11, SF5.
const std::vector<std::string_view>& named_glass_names();

}  // namespace gonio
