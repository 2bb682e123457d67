#include "gonio/spectrum/metal_spectra.h"

#include <utility>
#include <vector>

#include "gonio/spectrum/data_tables.h"

namespace gonio {

std::optional<MetalSpectra> named_metal_spectra(std::string_view name) {
  using namespace spectral_data;
  for (int m = 0; m < kMetalCount; ++m) {
    const MetalTable& t = kMetals[m];
    if (name != t.name) continue;
    std::vector<std::pair<double, double>> n, k;
    for (int i = 0; i < t.size; ++i) {
      n.emplace_back(t.lambda[i], t.n[i]);
      k.emplace_back(t.lambda[i], t.k[i]);
    }
    return MetalSpectra{PiecewiseLinearSpectrum::from_points(n, t.name), PiecewiseLinearSpectrum::from_points(k, t.name)};
  }
  return std::nullopt;
}

}  // namespace gonio
