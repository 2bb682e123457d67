#include "gonio/spectrum/glasses.h"

#include "gonio/spectrum/data_tables.h"

namespace gonio {

std::optional<PiecewiseLinearSpectrum> named_glass(std::string_view name) {
  using namespace spectral_data;
  for (int g = 0; g < kGlassCount; ++g) {
    const GlassTable& t = kGlasses[g];
    if (name != t.name) continue;
    std::vector<std::pair<double, double>> points;
    for (int i = 0; i < t.size; ++i) points.emplace_back(t.lambda[i], t.n[i]);
    return PiecewiseLinearSpectrum::from_points(points, t.name);
  }
  return std::nullopt;
}

const std::vector<std::string_view>& named_glass_names() {
  static const std::vector<std::string_view> names = [] {
    std::vector<std::string_view> v;
    for (int g = 0; g < spectral_data::kGlassCount; ++g) v.push_back(spectral_data::kGlasses[g].name);
    return v;
  }();
  return names;
}

}  // namespace gonio
