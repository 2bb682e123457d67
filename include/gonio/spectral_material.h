#pragma once
// Spectral mode's view of a material (issue 11; SPEC §1 "Spectral mode"). Parsing a
// material gives its RGB model and, beside it, what each colour parameter is as a
// spectrum: the spectrum given ({"spectrum": ...}, a named metal's measured n and k, a
// glass's index), or the smooth spectrum an RGB value is upsampled to (Jakob & Hanika
// 2019; rgb_to_spectrum.h). At a shading point, to_spectral() makes the same model type
// with those spectra evaluated at the path's 4 wavelengths: one model template serves both
// modes (bxdf.h).
//
// Dispersion: a dielectric (smooth or rough) whose index varies with λ refracts each
// wavelength its own way. The model is then made at the hero wavelength λ_0 and the
// secondary wavelengths are dropped (SampledWavelengths::terminate_secondary, Wilkie et
// al. 2014 §5, as pbrt-v4). A plastic's coat keeps its index at 550 nm (its tables and
// sampling state are made per index at parse time; the coat's dispersion changes its
// reflectance by well under 1 %).

#include <array>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json_fwd.hpp>

#include "gonio/bxdf.h"
#include "gonio/material.h"
#include "gonio/spectrum/spectrum.h"
#include "gonio/spectrum/wavelengths.h"

namespace gonio {

// The colour parameters (MaterialParam::Reflectance … MaterialParam::SheenColor).
inline constexpr int kColourParams = int(MaterialParam::SheenColor) + 1;

struct MaterialSpectra {
  // By MaterialParam; unset for a parameter the model does not have.
  std::array<std::optional<Spectrum>, kColourParams> colour;
  // A dielectric's, rough dielectric's or plastic's index n(λ); `dispersive` unless it
  // is one number.
  std::optional<Spectrum> index;
  bool dispersive = false;
  // A multiple-scattering rough conductor's F_avg(λ) = 2 ∫ F(μ, λ) μ dμ, or a dispersive
  // multiple-scattering rough dielectric's F̄(λ) seen from outside, tabulated every 5 nm at
  // parse time (the quadrature per wavelength would cost microseconds per shading point).
  std::optional<Spectrum> f_avg;
  // A blend's two parts.
  std::vector<MaterialSpectra> parts;
};

struct MaterialWithSpectra {
  BxDF bxdf;  // the RGB model, exactly what material_from_json gives
  MaterialSpectra spectra;
};

// material_from_json, with the spectra recorded (same checks, same errors).
MaterialWithSpectra material_with_spectra_from_json(const nlohmann::json& description, const std::string& where = "",
                                                    const std::string& base_dir = "");
MaterialWithSpectra parse_material_with_spectra(std::string_view json_text, std::string_view source = "material");

// Storage for the parts of blends made per shading point: reused from one to the next, so
// that making a spectral model allocates nothing once it has grown. One per thread.
class SpectralScratch {
 public:
  void reset() { used_ = 0; }
  std::array<SpectralBxDF, 2>* next_parts();

 private:
  std::vector<std::array<SpectralBxDF, 2>> parts_;
  size_t used_ = 0;
};

// Bit i set: colour parameter MaterialParam(i) of `rgb` comes from a texture, so its RGB
// value in `rgb` is upsampled rather than the material's spectrum used.
using TexturedColours = std::uint32_t;

// The model `rgb` (made from `spectra`, or with_params of such a model) at the
// wavelengths `w`. May terminate `w`'s secondary wavelengths (dispersion). A user model
// (CustomBxDF) has no spectral form and gives a black diffuse model. No exception.
SpectralBxDF to_spectral(const BxDF& rgb, const MaterialSpectra& spectra, SampledWavelengths& w,
                         SpectralScratch& scratch, TexturedColours textured = 0) noexcept;

// An RGB value of parameter `param` as a spectrum at `w`: a reflectance-like colour by
// Jakob & Hanika's upsampling (clamped to [0, 1]); a conductor's eta or k linearly
// interpolated between the channels' wavelengths 650, 550, 450 nm (constant beyond).
SampledSpectrum upsample_colour(MaterialParam param, const Color& rgb, const SampledWavelengths& w) noexcept;

}  // namespace gonio
