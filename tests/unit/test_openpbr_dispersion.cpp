// Dispersion of `openpbr` transmission in spectral mode (issue 35; SPEC-OPB "Dispersion";
// include/gonio/bxdf/openpbr_dispersion.h): the index against the definition of the Abbe
// number and against the specification's own constants, and the spectral model built at a
// path's hero wavelength.

#include <gtest/gtest.h>

#include <cmath>

#include "gonio/bxdf/openpbr_dispersion.h"
#include "gonio/material.h"
#include "gonio/spectral_material.h"

namespace gonio {
namespace {

// V = (η_d − 1)/(η_F − η_C) by definition, and η(λ_d) = η_d: the two conditions that fix
// Cauchy's A and B.
TEST(OpenPbrDispersion, IndexHasTheAbbeNumberAndTheIndexAtTheDLine) {
  for (const double eta_d : {1.33, 1.5, 1.9})
    for (const double v : {10.0, 20.0, 64.0}) {
      const double d = openpbr::cauchy_index(Float(eta_d), Float(v), Float(587.56));
      const double f = openpbr::cauchy_index(Float(eta_d), Float(v), Float(486.13));
      const double c = openpbr::cauchy_index(Float(eta_d), Float(v), Float(656.27));
      EXPECT_NEAR(d, eta_d, 1e-6);
      EXPECT_NEAR((eta_d - 1) / (f - c), v, 2e-3 * v) << eta_d << " " << v;
    }
}

// The specification's closed form, η_d + (η_d − 1)/V · (523655/λ² − 1.5168), written out.
TEST(OpenPbrDispersion, IndexIsTheSpecificationsFormula) {
  for (const double lambda : {380.0, 450.0, 550.0, 650.0, 780.0}) {
    const double spec = 1.5 + 0.5 / 20 * (523655 / (lambda * lambda) - 1.5168);
    EXPECT_NEAR(openpbr::cauchy_index(Float(1.5), Float(20), Float(lambda)), spec, 2e-5) << lambda;
  }
}

// In spectral mode the glass refracts with the index at the hero wavelength, and the path
// keeps only the hero; a material that does not disperse (scale 0, no transmission, or
// thin-walled) keeps η_d and all four wavelengths.
TEST(OpenPbrDispersion, SpectralModelRefractsWithTheHerosIndex) {
  const BxDF glass = parse_material(
      R"({"type": "openpbr", "transmission_weight": 1, "specular_ior": 1.5, "specular_roughness": 0.2,
          "transmission_dispersion_scale": 0.5, "transmission_dispersion_abbe_number": 30})");
  SpectralScratch scratch;
  for (const double lambda : {420.0, 520.0, 640.0}) {
    SampledWavelengths w = SampledWavelengths::single(Float(lambda));
    const SpectralBxDF s = to_spectral(glass, MaterialSpectra{}, w, scratch);
    const double expected = 1.5 + 0.5 / 60 * (523655 / (lambda * lambda) - 1.5168);
    EXPECT_NEAR(s.relative_eta(), expected, 1e-4) << lambda;
    EXPECT_TRUE(w.secondary_terminated()) << lambda;
  }
  for (const char* json :
       {R"({"type": "openpbr", "transmission_weight": 1, "specular_ior": 1.5, "transmission_dispersion_scale": 0})",
        R"({"type": "openpbr", "transmission_weight": 0, "specular_ior": 1.5, "transmission_dispersion_scale": 1})",
        R"({"type": "openpbr", "transmission_weight": 1, "geometry_thin_walled": true, "transmission_dispersion_scale": 1})"}) {
    SampledWavelengths w = SampledWavelengths::single(Float(420));
    (void)to_spectral(parse_material(json), MaterialSpectra{}, w, scratch);
    EXPECT_FALSE(w.secondary_terminated()) << json;
  }
  SampledWavelengths w = SampledWavelengths::single(Float(420));
  const SpectralBxDF plain = to_spectral(
      parse_material(R"({"type": "openpbr", "transmission_weight": 1, "specular_ior": 1.5})"), MaterialSpectra{}, w, scratch);
  EXPECT_NEAR(plain.relative_eta(), 1.5, 1e-6);
}

}  // namespace
}  // namespace gonio
