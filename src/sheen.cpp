// The sheen lobe's hemispherical average albedo (bxdf/sheen.h), from its build-time table.

#include "gonio/bxdf/sheen.h"

#include <algorithm>
#include <cmath>

namespace gonio {

Float sheen_average_albedo(Float roughness) {
  const Float x = std::clamp(roughness, Float(0), Float(1)) * (kSheenAverageSize - 1);
  if (!(x >= 0)) return tables::kSheenAverageAlbedo[0];  // NaN
  const int i = std::min(int(x), kSheenAverageSize - 2);
  const Float t = x - Float(i);
  return (1 - t) * tables::kSheenAverageAlbedo[i] + t * tables::kSheenAverageAlbedo[i + 1];
}

}  // namespace gonio
