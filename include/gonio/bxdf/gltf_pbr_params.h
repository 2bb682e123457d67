#pragma once
// The parameters of `gltf_pbr` (SPEC §2, "Wave 4"; the model is gltf_pbr.h): the glTF 2.0
// metallic-roughness material and its KHR_materials_* extensions under the input names of
// MaterialX 1.39's ND_gltf_pbr_surfaceshader, and the one table of them by JSON key that
// the parser, spectral mode and textures read (material.cpp, spectral_material.cpp), as
// openpbr_params.h does for openpbr. The registry (material_types.cpp) declares each one's
// default, range and meaning.

#include <array>
#include <cstddef>
#include <string_view>

#include "gonio/math/constants.h"

namespace gonio {

// U: Color or SampledSpectrum. `normal`, `clearcoat_normal` and `occlusion` are not here:
// the first two are shading normals (the renderer's), and a path tracer computes the
// occlusion that `occlusion` bakes (docs/gltf_pbr.md).
template <typename U>
struct GltfPbrParams {
  U base_color{Float(1)};                   // glTF 2.0 §3.9.2 baseColorFactor
  Float metallic = 1, roughness = 1;        // metallicFactor, roughnessFactor
  Float transmission = 0;                   // KHR_materials_transmission
  Float specular = 1;                       // KHR_materials_specular specularFactor
  U specular_color{Float(1)};               // specularColorFactor
  Float ior = Float(1.5);                   // KHR_materials_ior
  Float alpha = 1;                          // baseColorFactor's alpha
  Float alpha_mode = 0;                     // 0 OPAQUE, 1 MASK, 2 BLEND (MaterialX's enum)
  Float alpha_cutoff = Float(0.5);
  Float iridescence = 0, iridescence_ior = Float(1.3), iridescence_thickness = 100;  // nm
  U sheen_color{Float(0)};                  // KHR_materials_sheen
  Float sheen_roughness = 0;
  Float clearcoat = 0, clearcoat_roughness = 0;  // KHR_materials_clearcoat
  U emissive{Float(0)};                     // emissiveFactor
  Float emissive_strength = 1;              // KHR_materials_emissive_strength
  Float thickness = 0;                      // KHR_materials_volume (0: thin-walled)
  Float attenuation_distance = 0;           // 0 here means glTF's +infinity (no absorption)
  U attenuation_color{Float(1)};
  Float anisotropy_strength = 0, anisotropy_rotation = 0;  // KHR_materials_anisotropy (radians)
  Float dispersion = 0;                     // KHR_materials_dispersion (gonio extension of MaterialX's inputs)
  Float diffuse_transmission = 0;           // KHR_materials_diffuse_transmission (the same)
  U diffuse_transmission_color{Float(1)};
};

template <typename U>
struct GltfPbrField {
  std::string_view key;
  Float GltfPbrParams<U>::*number = nullptr;
  U GltfPbrParams<U>::*colour = nullptr;
  bool varying = true;  // may a texture drive it per hit (material.h, varying_param)
};

// In the registry's order (material_types.cpp), which is the order the parser reads them in.
// Not varying: ior (it bounds the medium of a volume), alpha_mode and alpha_cutoff (uniform
// in MaterialX), emissive_strength (uniform), the volume's attenuation (one medium per
// shape) and dispersion (a property of that medium).
template <typename U>
inline constexpr auto kGltfPbrFields = [] {
  using P = GltfPbrParams<U>;
  using F = GltfPbrField<U>;
  return std::array{
      F{"base_color", nullptr, &P::base_color},
      F{"metallic", &P::metallic},
      F{"roughness", &P::roughness},
      F{"transmission", &P::transmission},
      F{"specular", &P::specular},
      F{"specular_color", nullptr, &P::specular_color},
      F{"ior", &P::ior, nullptr, false},
      F{"alpha", &P::alpha},
      F{"alpha_mode", &P::alpha_mode, nullptr, false},
      F{"alpha_cutoff", &P::alpha_cutoff, nullptr, false},
      F{"iridescence", &P::iridescence},
      F{"iridescence_ior", &P::iridescence_ior, nullptr, false},
      F{"iridescence_thickness", &P::iridescence_thickness},
      F{"sheen_color", nullptr, &P::sheen_color},
      F{"sheen_roughness", &P::sheen_roughness},
      F{"clearcoat", &P::clearcoat},
      F{"clearcoat_roughness", &P::clearcoat_roughness},
      F{"emissive", nullptr, &P::emissive},
      F{"emissive_strength", &P::emissive_strength, nullptr, false},
      F{"thickness", &P::thickness},
      F{"attenuation_distance", &P::attenuation_distance, nullptr, false},
      F{"attenuation_color", nullptr, &P::attenuation_color, false},
      F{"anisotropy_strength", &P::anisotropy_strength},
      F{"anisotropy_rotation", &P::anisotropy_rotation},
      F{"dispersion", &P::dispersion, nullptr, false},
      F{"diffuse_transmission", &P::diffuse_transmission},
      F{"diffuse_transmission_color", nullptr, &P::diffuse_transmission_color},
  };
}();

inline constexpr std::size_t kGltfPbrFieldCount = kGltfPbrFields<Float>.size();

}  // namespace gonio
