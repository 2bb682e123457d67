#pragma once
// RGB → spectrum (SPEC §2: an RGB colour in spectral mode), by the sigmoid-polynomial
// method of Jakob & Hanika 2019, "A Low-Dimensional Function Space for Efficient Spectral
// Upsampling" (Eurographics): S(λ) = σ(c0 t² + c1 t + c2), σ(x) = 1/2 + x / (2√(1 + x²))
// (their eq. 3), with t the normalised wavelength of rgb_table_layout.h. The coefficients
// come from a table fitted at build time by tools/make_spectral_tables.cpp (their §4:
// Gauss–Newton on the CIELAB distance of the round trip under D65), looked up trilinearly.
//
// Reflectances (RgbAlbedoSpectrum): rgb in [0, 1], spectrum in [0, 1].
// Emission (RgbIlluminantSpectrum): rgb ≥ 0, E(λ) = m · S_{rgb/m}(λ) · D65(λ) with
// m = 2 max(rgb) and D65 normalised to luminance 1 (d65.h), as pbrt-v4's
// RGBIlluminantSpectrum: (1, 1, 1) gives m = 2, S = 1/2, E = D65, which is white.

#include "gonio/spectrum/d65.h"
#include "gonio/spectrum/rgb_table_layout.h"
#include "gonio/spectrum/wavelengths.h"

namespace gonio {

// σ(x) = 1/2 + x / (2√(1 + x²)), with σ(±∞) = 1 or 0 (and 0 for NaN, e.g. a NaN λ).
inline Float sigmoid_jh(Float x) {
  if (!(std::abs(x) < Float(1e18))) return x > 0 ? Float(1) : Float(0);  // ±∞, NaN, and x² overflow
  return Float(0.5) + x / (2 * std::sqrt(1 + x * x));
}

struct SigmoidPolynomial {
  // Coefficients of t², t, 1. A grey c ∈ [0, 1] is (0, 0, (c − 1/2)/√(c(1 − c))), ±∞ for
  // black and white (σ gives exactly 0 and 1 there).
  Float c0 = 0, c1 = 0, c2 = 0;

  Float eval(Float lambda) const {
    const Float t = (lambda - Float(rgb_table::kT0)) * Float(1 / rgb_table::kTSpan);
    return sigmoid_jh((c0 * t + c1) * t + c2);
  }
  SampledSpectrum eval(const SampledWavelengths& w) const {
    return {eval(w[0]), eval(w[1]), eval(w[2]), eval(w[3])};
  }
};

// The coefficients for rgb (each component clamped to [0, 1]; NaN counts as 0): exact
// greys handled in closed form, others by trilinear interpolation of the table.
SigmoidPolynomial rgb_to_sigmoid_polynomial(Float r, Float g, Float b);

// A reflectance given as linear sRGB in [0, 1].
class RgbAlbedoSpectrum {
 public:
  // Throws InputError unless every component is finite and within [0, 1].
  RgbAlbedoSpectrum(Float r, Float g, Float b);
  Float eval(Float lambda) const { return poly_.eval(lambda); }
  SampledSpectrum eval(const SampledWavelengths& w) const { return poly_.eval(w); }
  const SigmoidPolynomial& polynomial() const { return poly_; }

 private:
  SigmoidPolynomial poly_;
};

// An emission given as linear sRGB ≥ 0 (may exceed 1).
class RgbIlluminantSpectrum {
 public:
  static constexpr Float kMaxComponent = 1e9f;
  // Throws InputError unless every component is finite and within [0, kMaxComponent].
  RgbIlluminantSpectrum(Float r, Float g, Float b);
  // Without the validation, for values met per shading point (an environment map's
  // texel): negative or NaN components count as 0, those above kMaxComponent as it.
  static RgbIlluminantSpectrum clamped(const Color& rgb);
  // The one implementation of E(λ) = m · S_{rgb/m}(λ) · D65(λ); rgb_illuminant() and the
  // scene's RGB emissions all come here.
  Float eval(Float lambda) const { return scale_ * poly_.eval(lambda) * d65(lambda); }
  SampledSpectrum eval(const SampledWavelengths& w) const { return scale_ * poly_.eval(w) * d65(w); }
  Float scale() const { return scale_; }
  const SigmoidPolynomial& polynomial() const { return poly_; }

 private:
  RgbIlluminantSpectrum() = default;
  void set(Float r, Float g, Float b);  // components already in [0, kMaxComponent]

  Float scale_ = 0;  // m = 2 max(rgb)
  SigmoidPolynomial poly_;
};

// RgbIlluminantSpectrum::clamped(rgb).eval(w): an RGB emission at the wavelengths w without
// building (and validating) one. Negative or NaN components count as 0.
SampledSpectrum rgb_illuminant(const Color& rgb, const SampledWavelengths& w);

// An unbounded RGB quantity ≥ 0 (a measured BRDF value, 1/sr) at the wavelengths w: the
// same scaled sigmoid without the illuminant D65 (pbrt-v4's RGBUnboundedSpectrum). Negative or
// NaN components count as 0.
SampledSpectrum rgb_unbounded(const Color& rgb, const SampledWavelengths& w);

}  // namespace gonio
