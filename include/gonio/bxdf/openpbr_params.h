#pragma once
// OpenPBR Surface 1.1's parameters (SPEC-OPB "Parameter reference"; the model is
// openpbr.h) and the one table of them by JSON key that the parser, spectral mode and
// textures read (material.cpp, spectral_material.cpp), so that the list is written once
// more than the struct and the registry (material_types.cpp), not once per use.

#include <array>
#include <cstddef>
#include <string_view>

#include "gonio/math/constants.h"

namespace gonio {

// Every OpenPBR Surface 1.1 parameter (SPEC-OPB "Parameter reference"), OpenPBR's own units
// (thin_film_thickness in µm), plus gonio's rotations (fractions of a turn). U: Color or
// SampledSpectrum. Parameters a BSDF does not use (emission, the interior media,
// dispersion, subsurface radii) are kept so that the material round-trips.
template <typename U>
struct OpenPbrParams {
  Float base_weight = 1;
  U base_color{Float(0.8)};
  Float base_metalness = 0, base_diffuse_roughness = 0;
  Float specular_weight = 1;
  U specular_color{Float(1)};
  Float specular_roughness = Float(0.3), specular_roughness_anisotropy = 0, specular_ior = Float(1.5);
  Float specular_rotation = 0;
  Float transmission_weight = 0;
  U transmission_color{Float(1)};
  Float transmission_depth = 0;
  U transmission_scatter{Float(0)};
  Float transmission_scatter_anisotropy = 0, transmission_dispersion_scale = 0,
        transmission_dispersion_abbe_number = 20;
  Float subsurface_weight = 0;
  U subsurface_color{Float(0.8)};
  Float subsurface_radius = 1;
  U subsurface_radius_scale{Float(1)};
  Float subsurface_scatter_anisotropy = 0;
  Float coat_weight = 0;
  U coat_color{Float(1)};
  Float coat_roughness = 0, coat_roughness_anisotropy = 0, coat_ior = Float(1.6), coat_darkening = 1;
  Float coat_rotation = 0;
  Float fuzz_weight = 0;
  U fuzz_color{Float(1)};
  Float fuzz_roughness = Float(0.5);
  Float thin_film_weight = 0, thin_film_thickness = Float(0.5), thin_film_ior = Float(1.4);
  Float emission_luminance = 0;
  U emission_color{Float(1)};
  Float geometry_opacity = 1;
  bool geometry_thin_walled = false;
  // gonio extension: the coat and fuzz scale what lies below them by both directions'
  // albedos (reciprocal) instead of the view's (OpenPBR's default; openpbr.h).
  bool reciprocal_layering = false;
};


// One colour or number parameter of OpenPbrParams<U> (geometry_thin_walled and
// reciprocal_layering, flags, are not): exactly one of `number` and `colour` is set. What a change of it touches in
// OpenPbrBxDFT::make(), for with_params (material.h):
//  * `solved`: what make() solves by quadrature (openpbr::Solved): the diffuse's
//    normalisation b(μ) (the specular layer's E_s(μ) through its index, roughness and film,
//    and EON's kernel through base_diffuse_roughness), the film's change of E_s, the coat's
//    and the specular layer's average albedos, the glass's compensation lobe;
//  * `film`: RGB mode's film reflectance tables (the film on the specular layer's index and the
//    glass's; the metal's also reads its colours, which with_openpbr_params compares);
//  * `medium`: the glass's index, modulated_ior(specular_ior, specular_weight), which bounds
//    the medium behind a non-thin translucent base.
template <typename U>
struct OpenPbrField {
  std::string_view key;
  Float OpenPbrParams<U>::*number = nullptr;
  U OpenPbrParams<U>::*colour = nullptr;
  bool solved = false, film = false, medium = false;
};

// In the registry's order (material_types.cpp), which is the order the parser reads them in.
template <typename U>
inline constexpr auto kOpenPbrFields = [] {
  using P = OpenPbrParams<U>;
  using F = OpenPbrField<U>;
  return std::array{
      F{"base_weight", &P::base_weight},
      F{"base_color", nullptr, &P::base_color},
      F{"base_metalness", &P::base_metalness},
      F{"base_diffuse_roughness", &P::base_diffuse_roughness, nullptr, true},
      F{"specular_weight", &P::specular_weight, nullptr, true, true, true},
      F{"specular_color", nullptr, &P::specular_color},
      F{"specular_roughness", &P::specular_roughness, nullptr, true},
      F{"specular_roughness_anisotropy", &P::specular_roughness_anisotropy, nullptr, true},
      F{"specular_ior", &P::specular_ior, nullptr, true, true, true},
      F{"specular_rotation", &P::specular_rotation},
      F{"transmission_weight", &P::transmission_weight},
      F{"transmission_color", nullptr, &P::transmission_color},
      F{"transmission_depth", &P::transmission_depth},
      F{"transmission_scatter", nullptr, &P::transmission_scatter},
      F{"transmission_scatter_anisotropy", &P::transmission_scatter_anisotropy},
      F{"transmission_dispersion_scale", &P::transmission_dispersion_scale},
      F{"transmission_dispersion_abbe_number", &P::transmission_dispersion_abbe_number},
      F{"subsurface_weight", &P::subsurface_weight},
      F{"subsurface_color", nullptr, &P::subsurface_color},
      F{"subsurface_radius", &P::subsurface_radius},
      F{"subsurface_radius_scale", nullptr, &P::subsurface_radius_scale},
      F{"subsurface_scatter_anisotropy", &P::subsurface_scatter_anisotropy},
      F{"coat_weight", &P::coat_weight, nullptr, true, true},
      F{"coat_color", nullptr, &P::coat_color},
      F{"coat_roughness", &P::coat_roughness, nullptr, true},
      F{"coat_roughness_anisotropy", &P::coat_roughness_anisotropy, nullptr, true},
      F{"coat_ior", &P::coat_ior, nullptr, true, true},
      F{"coat_darkening", &P::coat_darkening},
      F{"coat_rotation", &P::coat_rotation},
      F{"fuzz_weight", &P::fuzz_weight},
      F{"fuzz_color", nullptr, &P::fuzz_color},
      F{"fuzz_roughness", &P::fuzz_roughness},
      F{"thin_film_weight", &P::thin_film_weight, nullptr, true},
      F{"thin_film_thickness", &P::thin_film_thickness, nullptr, true, true},
      F{"thin_film_ior", &P::thin_film_ior, nullptr, true, true},
      F{"emission_luminance", &P::emission_luminance},
      F{"emission_color", nullptr, &P::emission_color},
      F{"geometry_opacity", &P::geometry_opacity},
  };
}();

inline constexpr std::size_t kOpenPbrFieldCount = kOpenPbrFields<Float>.size();

}  // namespace gonio
