// Lookups into the build-time albedo tables (multiscatter.h).

#include "gonio/multiscatter.h"

#include <algorithm>
#include <cmath>

#include "gonio/multiscatter_table_layout.h"

namespace gonio {

namespace {
using namespace tables;

// Fractional row for α (rows are uniform in r = sqrt(α)).
Float row_of(Float alpha) {
  const Float r = std::sqrt(std::clamp(alpha, Float(0), Float(1)));
  return r * Float(kAlbedoRoughnessSize - 1);
}
}  // namespace

Float microfacet_albedo(MicrofacetType type, Float alpha, Float mu) {
  const auto& table = type == MicrofacetType::GGX ? kGgxAlbedo : kBeckmannAlbedo;
  const Float fr = row_of(alpha);
  const Float fc = std::clamp(mu, Float(0), Float(1)) * Float(kAlbedoCosineSize - 1);
  const int r0 = std::min(int(fr), kAlbedoRoughnessSize - 2), c0 = std::min(int(fc), kAlbedoCosineSize - 2);
  const Float tr = fr - Float(r0), tc = fc - Float(c0);
  const Float top = table[r0][c0] * (1 - tc) + table[r0][c0 + 1] * tc;
  const Float bottom = table[r0 + 1][c0] * (1 - tc) + table[r0 + 1][c0 + 1] * tc;
  return top * (1 - tr) + bottom * tr;
}

Float microfacet_average_albedo(MicrofacetType type, Float alpha) {
  const auto& table = type == MicrofacetType::GGX ? kGgxAverageAlbedo : kBeckmannAverageAlbedo;
  const Float fr = row_of(alpha);
  const int r0 = std::min(int(fr), kAlbedoRoughnessSize - 2);
  const Float tr = fr - Float(r0);
  return table[r0] * (1 - tr) + table[r0 + 1] * tr;
}

}  // namespace gonio
