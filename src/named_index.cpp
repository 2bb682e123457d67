#include "gonio/named_index.h"

#include <string>

#include "gonio/error.h"
#include "gonio/metals.h"
#include "gonio/spectrum/glasses.h"
#include "gonio/spectrum/metal_spectra.h"
#include "gonio/spectrum/spectrum_to_rgb.h"  // kRgbIndexWavelengths

namespace gonio {

std::vector<std::pair<double, double>> named_index(std::string_view name, std::optional<Float> nm) {
  std::vector<std::pair<double, double>> index;
  if (nm) {
    if (const auto metal = named_metal_spectra(name))
      index.emplace_back(metal->eta.eval(*nm), metal->k.eval(*nm));
    else if (const auto glass = named_glass(name))
      index.emplace_back(glass->eval(*nm), 0.0);
  } else if (const auto metal = named_metal(name)) {
    for (int c = 0; c < 3; ++c) index.emplace_back(metal->eta[c], metal->k[c]);
  } else if (const auto glass = named_glass(name)) {
    for (Float lambda : kRgbIndexWavelengths) index.emplace_back(glass->eval(lambda), 0.0);
  }
  if (index.empty()) {
    std::string known;
    for (auto n : named_metal_names()) known += (known.empty() ? "" : ", ") + std::string(n);
    for (auto n : named_glass_names()) known += ", " + std::string(n);
    throw InputError("--material: unknown material \"" + std::string(name) + "\" (known: " + known + ")");
  }
  return index;
}

void check_fresnel_index(double eta, double k) {
  constexpr double kMin = 1e-4, kMax = 1e4;
  if (!(eta >= kMin && eta <= kMax))
    throw InputError("--eta must be in [" + format_number(kMin) + ", " + format_number(kMax) + "], got " +
                     format_number(eta));
  if (!(k >= 0 && k <= kMax))
    throw InputError("--k must be in [0, " + format_number(kMax) + "], got " + format_number(k));
}

}  // namespace gonio
