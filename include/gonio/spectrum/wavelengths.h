#pragma once
// The wavelengths of one path: hero-wavelength sampling (Wilkie, Nawaz, Droske, Weidlich
// and Hanika 2014, "Hero Wavelength Spectral Sampling", EGSR), 4 wavelengths per path,
// importance-sampled over the visible range [kLambdaMin, kLambdaMax].
//
// Two densities. The renderer draws with the sRGB-response density (below the visible
// one; issue 38). The visible density is pbrt-v4's visible-importance function (after
// Radziszewski et al. 2009), kept as the reference it is measured against:
// p(λ) ∝ sech²(a (λ − μ)) with a = 0.0072 /nm, μ = 538 nm, restricted to [360, 830] nm.
// It follows the luminous sensitivity (ȳ peaks at 555 nm) with heavier tails than ȳ, so
// that blue and red are still sampled. Its CDF is closed-form:
//   P(λ) = (tanh(a (λ − μ)) − t0) / (t1 − t0),  t0 = tanh(a (360 − μ)), t1 = tanh(a (830 − μ))
//   p(λ) = a sech²(a (λ − μ)) / (t1 − t0)
//   P⁻¹(u) = μ + atanh(t0 + u (t1 − t0)) / a
// The rotations are taken in CDF space (Wilkie et al. 2014, §4, applied to the CDF):
// λ_j = P⁻¹(frac(u + j/4)); every λ_j is distributed with density p on its own, so each
// is weighted by its own p(λ_j) and the mean of the four estimates is unbiased.

#include <algorithm>
#include <array>
#include <cmath>

#include "gonio/spectrum/data_tables.h"
#include "gonio/spectrum/sampled_spectrum.h"

namespace gonio {

namespace visible_density {
inline constexpr Float kA = 0.0072f;   // 1/nm
inline constexpr Float kMu = 538.0f;   // nm
// tanh(a (360 − μ)) and tanh(a (830 − μ)), computed in double (tests recompute them).
inline constexpr Float kT0 = -0.856910625469828f;
inline constexpr Float kT1 = 0.9705913469402698f;
inline constexpr Float kSpan = 1.8275019724100978f;  // t1 − t0
}  // namespace visible_density

// p(λ) in 1/nm; 0 outside [kLambdaMin, kLambdaMax].
inline Float visible_wavelength_pdf(Float lambda) {
  using namespace visible_density;
  if (!(lambda >= kLambdaMin && lambda <= kLambdaMax)) return 0;
  const Float c = std::cosh(kA * (lambda - kMu));
  return kA / (kSpan * c * c);
}

// P(λ), clamped to [0, 1].
inline Float visible_wavelength_cdf(Float lambda) {
  using namespace visible_density;
  if (!(lambda > kLambdaMin)) return 0;
  if (!(lambda < kLambdaMax)) return 1;
  return std::clamp((std::tanh(kA * (lambda - kMu)) - kT0) / kSpan, Float(0), Float(1));
}

// P⁻¹(u) for u in [0, 1] (other u are clamped), in [kLambdaMin, kLambdaMax].
inline Float sample_visible_wavelength(Float u) {
  using namespace visible_density;
  u = std::clamp(u, Float(0), Float(1));
  const Float t = std::clamp(kT0 + u * kSpan, kT0, kT1);
  return std::clamp(kMu + std::atanh(t) / kA, kLambdaMin, kLambdaMax);
}

// The renderer's density (issue 38): per 1 nm bin, p ∝ ‖(r̄, ḡ, b̄)‖^½, the linear-sRGB
// colour-matching functions (CIE 1931 through the IEC 61966-2-1 matrix) at the bin's
// centre; tabulated at build time (tools/make_spectral_tables.cpp, kResponseCdf). The
// film's three channels are estimated from every wavelength, so a density that follows
// all three — the blue and red ends included, where z̄ and x̄'s lobes are and the visible
// density above thins out — gives less colour noise. The exponent ½ is measured, not
// derived: with the four rotations and a low-discrepancy u the wavelengths are already
// stratified, and a flatter density than the one-sample optimum (exponent 1, for a flat
// spectrum) did better on every scene tried (docs/benchmarks.md, "Spectral noise").
// Every bin has a positive density, so every wavelength a CMF sees can be drawn.
inline Float response_wavelength_pdf(Float lambda) {
  using namespace spectral_data;
  if (!(lambda >= kLambdaMin && lambda <= kLambdaMax)) return 0;
  const int i = std::min(int(lambda - kLambdaMin), kCieSamples - 2);
  return Float(kResponseCdf[i + 1] - kResponseCdf[i]);  // bins are 1 nm wide
}

// P⁻¹(u) for u in [0, 1): the bin from the guide table and a forward scan (one step or
// none in most of the range), uniform within it; pdf receives p(λ).
inline Float sample_response_wavelength(Float u, Float& pdf) {
  using namespace spectral_data;
  const double v = std::clamp(double(u), 0.0, 1.0);
  // The last edge ≤ v, among the first kCieSamples − 1 (so that v = 1 lands in the last bin).
  int i = kResponseGuide[std::min(int(v * kResponseGuideSize), kResponseGuideSize - 1)];
  while (i < kCieSamples - 2 && kResponseCdf[i + 1] <= v) ++i;
  const double mass = kResponseCdf[i + 1] - kResponseCdf[i];
  pdf = Float(mass);
  const double t = mass > 0 ? std::clamp((v - kResponseCdf[i]) / mass, 0.0, 1.0) : 0.5;
  return std::min(Float(kLambdaMin + i + t), Float(kLambdaMin + i + 1));
}

class SampledWavelengths {
 public:
  // Hero-wavelength sampling: λ_j = P⁻¹(frac(u + j/4)), pdf_j = p(λ_j), u in [0, 1), with
  // the visible density (a reference for tests and benchmarks).
  static SampledWavelengths sample_visible(Float u) {
    return rotated(u, [](Float uj, Float& pdf) {
      using namespace visible_density;
      // t = tanh(a (λ − μ)) = t0 + u (t1 − t0); then λ = μ + atanh(t)/a with
      // atanh(t) = ½ log((1 + t)/(1 − t)), and p(λ) = a sech² / span = a (1 − t²) / span:
      // one log per wavelength, no cosh.
      const Float t = std::clamp(kT0 + uj * kSpan, kT0, kT1);
      pdf = kA * (1 - t * t) / kSpan;
      return std::clamp(kMu + Float(0.5) / kA * std::log((1 + t) / (1 - t)), kLambdaMin, kLambdaMax);
    });
  }
  // The same rotations with the sRGB-response density above: the renderer's draw.
  static SampledWavelengths sample_response(Float u) { return rotated(u, sample_response_wavelength); }
  // Uniform over [kLambdaMin, kLambdaMax] with the same rotation (a reference to compare
  // the importance density with): λ_j = 360 + 470 frac(u + j/4), pdf 1/470.
  static SampledWavelengths sample_uniform(Float u) {
    return rotated(u, [](Float uj, Float& pdf) {
      pdf = 1 / (kLambdaMax - kLambdaMin);
      return std::min(kLambdaMin + uj * (kLambdaMax - kLambdaMin), kLambdaMax);
    });
  }

  // All 4 slots at one wavelength with density 1: a model evaluated at λ (`gonio eval
  // --wavelength`, tests), not an estimator. λ is clamped to [kLambdaMin, kLambdaMax].
  static SampledWavelengths single(Float lambda) {
    SampledWavelengths w;
    const Float l = std::isnan(lambda) ? Float(550) : std::clamp(lambda, kLambdaMin, kLambdaMax);
    w.lambda_.fill(l);
    w.pdf_.fill(1);
    return w;
  }

  static constexpr int size() { return kSpectrumSamples; }
  Float operator[](int j) const { return lambda_[size_t(j)]; }
  Float pdf(int j) const { return pdf_[size_t(j)]; }
  SampledSpectrum pdf() const { return {pdf_[0], pdf_[1], pdf_[2], pdf_[3]}; }

  // For a wavelength-dependent scattering event (dispersion): the path goes on with the
  // hero only. λ_1..3 get pdf 0 (their estimates count as 0) and the hero's density is
  // divided by 4, so that the mean over the 4 slots, (1/4) f(λ_0) / (p(λ_0)/4), is still
  // an unbiased estimate (Wilkie et al. 2014, §5; as pbrt-v4 does). Idempotent.
  void terminate_secondary() {
    if (secondary_terminated()) return;
    for (int j = 1; j < kSpectrumSamples; ++j) pdf_[size_t(j)] = 0;
    pdf_[0] /= kSpectrumSamples;
  }
  bool secondary_terminated() const {
    for (int j = 1; j < kSpectrumSamples; ++j)
      if (pdf_[size_t(j)] != 0) return false;
    return true;
  }

 private:
  // The rotations in CDF space: λ_j = inverse(frac(u + j/4)), which also sets pdf_j. A u
  // outside [0, 1) is clamped (NaN → 0).
  template <typename Inverse>
  static SampledWavelengths rotated(Float u, Inverse&& inverse) {
    SampledWavelengths w;
    if (!(u >= 0 && u < 1)) u = u >= 1 ? kOneMinusEpsilon : Float(0);
    for (int j = 0; j < kSpectrumSamples; ++j) {
      Float uj = u + Float(j) / kSpectrumSamples;
      if (uj >= 1) uj -= 1;
      w.lambda_[size_t(j)] = inverse(uj, w.pdf_[size_t(j)]);
    }
    return w;
  }

  std::array<Float, kSpectrumSamples> lambda_{};
  std::array<Float, kSpectrumSamples> pdf_{};
};

}  // namespace gonio
