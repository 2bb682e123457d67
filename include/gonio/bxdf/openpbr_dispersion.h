#pragma once
// Dispersion of an `openpbr` material's transmission in spectral mode (issue 35; SPEC-OPB
// "Dispersion"): the interface's index varies with the wavelength as Cauchy's two-term
// formula η(λ) = A + B/λ², fixed by the index at the Fraunhofer d line, η_d =
// `specular_ior`, and the Abbe number V = `transmission_dispersion_abbe_number` /
// `transmission_dispersion_scale`, V = (η_d − 1)/(η_F − η_C):
//   B = (η_d − 1) / (V (1/λ_F² − 1/λ_C²)),   η(λ) = η_d + B (1/λ² − 1/λ_d²),
// with λ_d = 587.56 nm, λ_F = 486.13 nm, λ_C = 656.27 nm (the helium d and hydrogen F and C
// lines that define the Abbe number). The spec writes the same as
// η_d + (η_d − 1)/V · (523655/λ² − 1.5168).

#include <optional>

#include "gonio/bxdf/openpbr.h"

namespace gonio::openpbr {

inline constexpr double kLambdaD = 587.56, kLambdaF = 486.13, kLambdaC = 656.27;  // nm

// The index at wavelength lambda_nm for index eta_d at the d line and Abbe number v (> 0).
inline Float cauchy_index(Float eta_d, Float v, Float lambda_nm) {
  const double b = (double(eta_d) - 1) / (double(v) * (1 / (kLambdaF * kLambdaF) - 1 / (kLambdaC * kLambdaC)));
  const double l = double(lambda_nm);
  return Float(double(eta_d) + b * (1 / (l * l) - 1 / (kLambdaD * kLambdaD)));
}

// The index the material's interface has at the path's hero wavelength when it disperses:
// it transmits (not thin-walled: a sheet does not bend light) with a dispersion scale > 0.
// nullopt otherwise (no dispersion: the index is specular_ior at every wavelength).
template <typename U>
std::optional<Float> dispersed_ior(const OpenPbrParams<U>& p, Float lambda_nm) {
  if (!(p.transmission_weight > 0) || p.geometry_thin_walled || !(p.transmission_dispersion_scale > 0) ||
      !(p.transmission_dispersion_abbe_number > 0))
    return std::nullopt;
  const Float v = p.transmission_dispersion_abbe_number / p.transmission_dispersion_scale;
  return cauchy_index(p.specular_ior, v, lambda_nm);
}

}  // namespace gonio::openpbr
