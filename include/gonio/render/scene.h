#pragma once
// A scene in memory: camera, materials, shapes and lights, as scene_loader.h reads them
// from JSON (docs/scene-format.md). Shapes are spheres and triangle meshes (quads and
// OBJ files become meshes); area lights are shapes too, so that rays can hit them.

#include <array>
#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "gonio/bxdf.h"
#include "gonio/spectral_material.h"
#include "gonio/math/warp.h"
#include "gonio/render/sampler.h"
#include "gonio/render/camera.h"
#include "gonio/render/light_sampler.h"
#include "gonio/render/lights.h"
#include "gonio/render/texture.h"
#include "gonio/spectrum/rgb_to_spectrum.h"
#include "gonio/subsurface/diffusion.h"
#include "gonio/subsurface/subsurface.h"
#include "gonio/subsurface/sw_bxdf.h"

namespace gonio::render {

struct Material {
  std::string name;
  BxDF bxdf;
  // Parameters that vary over the surface, at most one texture per parameter; empty for
  // a uniform material.
  std::vector<ParamTexture> textures;
  // Spectral mode: what the colour parameters are as spectra, and which of them come
  // from textures (upsampled from the texture's RGB at each shading point).
  MaterialSpectra spectra;
  TexturedColours textured_colours = 0;
  // A `subsurface` material (issue 14): `bxdf` is its boundary, and the medium inside
  // the shape is walked (random walk) or replaced by its diffusion profile, made once
  // at load. Empty for every other material.
  std::optional<Subsurface> subsurface;
  std::shared_ptr<const DiffusionProfile> profile;
  SwBxDF exit_lobe;  // the diffusion method's Sw (its Fresnel moment is a quadrature: made once)
  // `openpbr` (issue 35, docs/openpbr.md "Rendering"): whether the surface emits
  // (emission_luminance > 0; OpenPbrBxDFT::emission gives its radiance), from the side its
  // geometric normal points to, or both sides when thin-walled.
  bool emits = false, emits_both_sides = false;
  // `openpbr` with transmission_depth > 0 and no scattering: the absorption coefficient of
  // the medium filling the shape (subsurface/openpbr_interior.h), applied as exp(−σa t) to
  // light crossing it; the colour it came from, for spectral mode. (With scattering the
  // medium is `subsurface`'s and is walked.)
  std::optional<Color> absorption;
  std::optional<RgbAlbedoSpectrum> absorption_colour;
  Float absorption_depth = 1;
  // `openpbr` with a medium inside its shape: the model for a vertex whose wo is inside
  // (behind the geometric normal): the transmitting interface alone (scene_loader.cpp,
  // inside_model). Unset: `bxdf` from both sides.
  std::optional<BxDF> inside;
  // `subsurface` is an openpbr material's volume form (scene_loader.cpp, subsurface_volume):
  // RGB renders walk it; spectral and polarized ones shade `bxdf`, its BSDF form, instead.
  bool subsurface_bsdf_fallback = false;
  // Light shapes' material: absorbs everything, so a path ends where it hits one.
  bool black_body = false;

  // The model at texture coordinates `uv`: `bxdf` itself for a uniform material (no
  // copy), else `bxdf` with the textured parameters looked up, built in `scratch`.
  const BxDF& at(const Vec2& uv, std::optional<BxDF>& scratch) const {
    if (textures.empty()) return bxdf;
    std::array<ParamValue, kMaterialParamCount> values;
    size_t n = 0;
    for (const ParamTexture& t : textures) values[n++] = {t.param, t.texture.eval(uv)};
    return scratch.emplace(with_params(bxdf, {values.data(), n}));
  }
};

// Indexed triangles with optional per-vertex normals, UVs and tangents (each either empty
// or one per position).
struct Mesh {
  std::vector<Vec3> positions, normals, tangents;
  std::vector<Vec2> uvs;
  std::vector<std::uint32_t> indices;  // 3 per triangle
  int material = -1;
  int area_light = -1;  // index into Scene::area_lights when the mesh emits
};

struct Sphere {
  Vec3 center;
  Float radius = 1;
  int material = -1;
  int area_light = -1;
};

struct RenderSettings {
  int spp = 16;
  int max_depth = 16;   // bounces
  int rr_depth = 3;     // Russian roulette from this bounce on
  std::uint64_t seed = 0;
  Float exposure = 0;   // stops, for PNG output
  bool filmic = true;   // tone map for PNG output (else clamp)
  bool spectral = false;  // hero-wavelength spectral transport (else RGB)
  bool polarized = false;  // Stokes vectors along paths (issue 15), RGB or spectral
  SamplerType sampler = SamplerType::ZSobol;  // sampler.h
  LightSamplerType light_sampler = LightSamplerType::Bvh;  // light_sampler.h
};

struct Scene {
  Camera camera;
  RenderSettings settings;
  std::vector<Material> materials;
  std::vector<Mesh> meshes;
  std::vector<Sphere> spheres;
  std::vector<PointLight> point_lights;
  std::vector<AreaLight> area_lights;
  // Per area light, the material whose emission it is (an emitting `openpbr` sphere or
  // quad, which also reflects), or -1 for a light of the scene's "lights".
  std::vector<int> area_light_material;
  Environment environment;
};

}  // namespace gonio::render
