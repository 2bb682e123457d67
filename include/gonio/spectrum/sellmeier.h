#pragma once
// Refractive index from Sellmeier coefficients ({"sellmeier": {"B": [..], "C": [..]}},
// SPEC §2):  n²(λ) = 1 + Σ_i B_i λ² / (λ² − C_i),  λ in µm, C_i in µm²
// (Sellmeier 1871; the form of the Schott catalogue).

#include <array>
#include <string_view>

#include "gonio/spectrum/wavelengths.h"

namespace gonio {

class SellmeierSpectrum {
 public:
  // Throws InputError naming `what` unless every coefficient is finite, C_i ≥ 0, no pole
  // λ² = C_i lies within [360, 830] nm, and n(λ) there is within [1e-4, 1e4] (the index
  // range of the material descriptions).
  SellmeierSpectrum(const std::array<double, 3>& b, const std::array<double, 3>& c,
                    std::string_view what = "sellmeier");

  Float eval(Float lambda) const;
  SampledSpectrum eval(const SampledWavelengths& w) const {
    return {eval(w[0]), eval(w[1]), eval(w[2]), eval(w[3])};
  }
  // n at λ in nm, in double (for references and tables).
  double index(double lambda_nm) const;

 private:
  std::array<double, 3> b_, c_;
};

}  // namespace gonio
