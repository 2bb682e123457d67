#pragma once
// The CIE 1931 2° standard observer (data/cie/cie1931_2deg_cmf.csv, 1 nm steps,
// interpolated linearly) and spectra → XYZ.
//
// Normalisation. XYZ of a spectral radiance L(λ) is
//   X = ∫ L x̄ dλ / ∫ ȳ dλ   (Y, Z likewise), over 360–830 nm,
// so a constant L = 1 has Y = 1: XYZ are in the units of L, with Y the luminance
// relative to a flat spectrum of the same radiance (no 683 lm/W). A reflectance ρ(λ)
// under D65 normalised to Y = 1 (d65.h) has XYZ = ∫ ρ D65 x̄ / ∫ ȳ, so ρ = 1 gives D65's
// white point (0.9505, 1, 1.089) and linear sRGB (1, 1, 1).

#include "gonio/spectrum/color_space.h"
#include "gonio/spectrum/data_tables.h"
#include "gonio/spectrum/wavelengths.h"

namespace gonio {

// x̄, ȳ, z̄ at λ (nm); 0 outside [360, 830].
inline XYZ cie_xyz_bar(Float lambda) {
  using namespace spectral_data;
  if (!(lambda >= kLambdaMin && lambda <= kLambdaMax)) return {};
  const Float f = lambda - Float(kCieFirstNm);
  const int i = std::min(int(f), kCieSamples - 2);
  const Float t = f - Float(i);
  return {kCieX[i] + t * (kCieX[i + 1] - kCieX[i]), kCieY[i] + t * (kCieY[i + 1] - kCieY[i]),
          kCieZ[i] + t * (kCieZ[i + 1] - kCieZ[i])};
}

// ∫ ȳ dλ over 360–830 nm of the linear interpolant (trapezoid rule on the 1 nm table).
inline double cie_y_integral() { return spectral_data::kCieYIntegral; }

// Monte Carlo estimate of XYZ from the values at one path's wavelengths:
//   X ≈ (1/4) Σ_j S(λ_j) x̄(λ_j) / p(λ_j) / ∫ȳ
// (a wavelength with pdf 0, dropped by terminate_secondary, counts 0).
inline XYZ to_xyz(const SampledSpectrum& s, const SampledWavelengths& w) {
  Float x = 0, y = 0, z = 0;
  for (int j = 0; j < kSpectrumSamples; ++j) {
    const Float p = w.pdf(j);
    if (!(p > 0)) continue;
    const XYZ bar = cie_xyz_bar(w[j]);
    const Float v = s[j] / p;
    x += v * bar.x;
    y += v * bar.y;
    z += v * bar.z;
  }
  const Float k = Float(1 / (kSpectrumSamples * spectral_data::kCieYIntegral));
  return {x * k, y * k, z * k};
}

// XYZ of f(λ) (normalised as above) by the trapezoid rule on the 1 nm grid of the table.
template <typename Fn>
XYZ integrate_xyz(Fn&& f) {
  using namespace spectral_data;
  double x = 0, y = 0, z = 0;
  for (int i = 0; i < kCieSamples; ++i) {
    const double wgt = (i == 0 || i == kCieSamples - 1) ? 0.5 : 1.0;
    const double v = wgt * double(f(double(kCieFirstNm + i)));
    x += v * kCieX[i];
    y += v * kCieY[i];
    z += v * kCieZ[i];
  }
  const double n = cie_y_integral();
  return {Float(x / n), Float(y / n), Float(z / n)};
}

}  // namespace gonio
