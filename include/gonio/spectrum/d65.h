#pragma once
// The CIE standard illuminant D65 ({"illuminant": "D65"}, SPEC §2), normalised to
// luminance 1: D65(λ) / Y_D65 with Y_D65 = ∫ D65 ȳ / ∫ ȳ (cie.h). Interpolated linearly
// between the 5 nm rows of data/cie/cie_illuminant_d65.csv.

#include "gonio/spectrum/data_tables.h"
#include "gonio/spectrum/wavelengths.h"

namespace gonio {

// The normalisation factor 1 / Y_D65 applied to the tabulated values.
inline double d65_scale() { return spectral_data::kD65Scale; }

// Normalised D65 at λ in nm (0 outside the table's range, 300–830 nm).
inline Float d65(Float lambda) {
  using namespace spectral_data;
  const Float f = (lambda - Float(kD65FirstNm)) / Float(kD65StepNm);
  if (!(f >= 0 && f <= Float(kD65Samples - 1))) return 0;
  const int i = std::min(int(f), kD65Samples - 2);
  const Float t = f - Float(i);
  return Float(kD65Scale) * (kD65[i] + t * (kD65[i + 1] - kD65[i]));
}
inline SampledSpectrum d65(const SampledWavelengths& w) { return {d65(w[0]), d65(w[1]), d65(w[2]), d65(w[3])}; }

}  // namespace gonio
