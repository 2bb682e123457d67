// RGB mode's thin-film reflectance table (bxdf/thin_film.h): at each tabulated cos θ1 the
// film's reflectance spectrum, sampled at every nanometre of the CIE tables, reduced to
// linear sRGB by spectrum_to_rgb (SpectrumUse::kReflectance) — the very reduction `gonio
// spectrum` applies to a reflectance (XYZ under D65 normalised by ∫ D65 ȳ, clamped to
// [0, 1]). Piecewise-linear through those samples, the spectrum is exactly the Airy sum at
// each nanometre the integration reads.

#include <cmath>
#include <utility>
#include <vector>

#include "gonio/bxdf/thin_film.h"
#include "gonio/spectrum/cie.h"
#include "gonio/spectrum/piecewise_linear.h"
#include "gonio/spectrum/spectrum.h"

namespace gonio {

std::shared_ptr<const ThinFilmRgbTable> make_thin_film_rgb_table(
    double thickness, double nf, const std::function<std::pair<double, double>(double)>& substrate) {
  using namespace spectral_data;
  auto table = std::make_shared<ThinFilmRgbTable>();
  table->r.resize(size_t(ThinFilmRgbTable::kEntries));
  std::vector<std::pair<double, double>> index(static_cast<size_t>(kCieSamples));
  for (int l = 0; l < kCieSamples; ++l) index[size_t(l)] = substrate(double(kCieFirstNm + l));
  std::vector<std::pair<double, double>> points(static_cast<size_t>(kCieSamples));
  // The substrate's critical angle from outside, where its index (at 550 nm, the index RGB
  // mode refracts with) is real and below 1.
  const auto [n550, k550] = substrate(550.0);
  if (k550 == 0 && n550 < 1) table->c0 = Float(std::sqrt(1 - n550 * n550));
  for (int i = 0; i < ThinFilmRgbTable::kEntries; ++i) {
    const double c = table->cos_of(i);
    for (int l = 0; l < kCieSamples; ++l) {
      const double lambda = double(kCieFirstNm + l);
      const auto [n, k] = index[size_t(l)];
      points[size_t(l)] = {lambda, airy_film<double>(c, nf, thickness, n, k, lambda).R()};
    }
    table->r[size_t(i)] = spectrum_to_rgb(Spectrum(PiecewiseLinearSpectrum::from_points(points, "thin film")),
                                          SpectrumUse::kReflectance);
  }
  table->substrate = std::move(index);
  return table;
}

}  // namespace gonio
