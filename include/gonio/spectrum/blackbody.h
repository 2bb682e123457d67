#pragma once
// Blackbody emission ({"blackbody": kelvin}, SPEC §2): Planck's law
//   B(λ, T) = 2 h c² / λ⁵ / (exp(h c / (λ k T)) − 1)
// scaled so that its luminance is 1 (Y = ∫ s B ȳ / ∫ ȳ = 1, cie.h), like RGB emission
// and the D65 illuminant: the temperature sets the colour, the emitter's scale the power.

#include "gonio/spectrum/wavelengths.h"

namespace gonio {

// Planck's spectral radiance in W / (m² sr m) at λ in nm (double, unnormalised).
double planck(double lambda_nm, double kelvin);

class BlackbodySpectrum {
 public:
  static constexpr double kMinKelvin = 100, kMaxKelvin = 1e6;
  // Throws InputError unless kMinKelvin ≤ kelvin ≤ kMaxKelvin.
  explicit BlackbodySpectrum(double kelvin);

  Float eval(Float lambda) const;
  SampledSpectrum eval(const SampledWavelengths& w) const {
    return {eval(w[0]), eval(w[1]), eval(w[2]), eval(w[3])};
  }
  double kelvin() const { return kelvin_; }

 private:
  double kelvin_;
  double scale_;  // 1 / Y of the unnormalised B
};

}  // namespace gonio
