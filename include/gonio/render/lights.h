#pragma once
// Light sources. Point lights are summed over exactly, the lecture's eq. 2
// (L = Σ f · I/r² · cos θ); area lights and the environment are integrated as eq. 1 by
// sampling them (next-event estimation) and by following BSDF samples that hit them,
// combined with multiple importance sampling.

#include <algorithm>
#include <optional>
#include <variant>
#include <vector>

#include "gonio/color.h"
#include "gonio/spectrum/spectrum.h"
#include "gonio/math/frame.h"
#include "gonio/math/vec3.h"
#include "gonio/math/warp.h"
#include "gonio/render/image.h"

namespace gonio::render {

// Isotropic point source of radiant intensity I (W/sr).
// Each light's colour is given twice: as linear sRGB for RGB mode and, for spectral
// mode, as the emission spectrum it came from (unset: the RGB value upsampled as an
// illuminant, rgb_illuminant()).
// A spot light (KHR_lights_punctual) is a point light whose intensity is scaled by
// spot_factor(); a directional light (`directional`) sends irradiance `intensity` along
// `direction` from infinitely far (position unused).
struct PointLight {
  Vec3 position;
  Color intensity{1};
  std::optional<Spectrum> spectrum;
  Vec3 direction{0, 0, -1};  // where a spot or directional light points
  Float cos_outer = -2, cos_inner = -2;  // a spot when cos_outer > -1
  bool directional = false;
};

// The spot's angular falloff towards `to_receiver` (unit, from the light): 1 inside the
// inner cone, 0 outside the outer one, and between them the smooth falloff that the
// KHR_lights_punctual specification gives ("Inner and Outer Cone Angles"):
// t = clamp((cos θ − cos outer) / max(0.001, cos inner − cos outer), 0, 1), factor t².
inline Float spot_factor(const PointLight& l, const Vec3& to_receiver) {
  if (!(l.cos_outer > -1)) return 1;
  const Float cd = dot(l.direction, to_receiver);
  const Float t = std::clamp((cd - l.cos_outer) / std::max(Float(0.001), l.cos_inner - l.cos_outer), Float(0), Float(1));
  return t * t;
}

// Parallelogram corner + s·edge1 + t·edge2, emitting radiance L from the side its normal
// edge1 × edge2 points to (both sides when two_sided).
struct QuadLight {
  Vec3 corner, edge1{1, 0, 0}, edge2{0, 0, 1};
  Color radiance{1};
  bool two_sided = false;
  std::optional<Spectrum> spectrum;

  Vec3 normal() const { return normalize(cross(edge1, edge2)); }
  Float area() const { return length(cross(edge1, edge2)); }
};

// Sphere emitting radiance L outwards, uniformly.
struct SphereLight {
  Vec3 center;
  Float radius = 1;
  Color radiance{1};
  std::optional<Spectrum> spectrum;
};

// A direction towards a light, the radiance arriving along it, and its density per unit
// solid angle at the receiving point (0 for delta lights).
struct LightSample {
  Vec3 wi;
  Float distance = 0;  // to the emitting point; infinite for the environment
  Color radiance;
  Float pdf = 0;
};

// Distant light from every direction: constant radiance, or a lat-long (equirectangular)
// map whose +y row 0 is straight up, importance-sampled by luminance.
class Environment {
 public:
  Environment() = default;
  explicit Environment(Color radiance, std::optional<Spectrum> spectrum = std::nullopt)
      : constant_(radiance), constant_spectrum_(std::move(spectrum)) {}
  Environment(Image map, Float scale, Float rotation_deg);

  bool is_black() const { return map_.width() == 0 && constant_.is_black(); }
  Color radiance(const Vec3& dir) const;
  // Spectral mode: the constant's spectrum, or the map's texel upsampled as an illuminant.
  SampledSpectrum radiance(const Vec3& dir, const SampledWavelengths& w) const;
  LightSample sample(Float u1, Float u2) const;
  Float pdf(const Vec3& dir) const;
  // The radiance averaged over the sphere of directions and the colour's channels (the
  // power estimate of light selection, light_sampler.h).
  Float mean_radiance() const { return map_.width() == 0 ? constant_.average() : mean_; }

 private:
  Color constant_;
  std::optional<Spectrum> constant_spectrum_;
  Image map_;
  Float scale_ = 1, rotation_ = 0;
  // Piecewise-constant 2-D distribution over the map's pixels (rows then columns).
  std::vector<Float> row_cdf_, col_cdf_;  // row_cdf_: height+1; col_cdf_: height×(width+1)
  Float total_ = 0;
  Float mean_ = 0;  // mean_radiance() of a map
  Vec2 direction_to_uv(const Vec3& dir) const;
  Vec3 uv_to_direction(Float u, Float v) const;
};

using AreaLight = std::variant<QuadLight, SphereLight>;

// Samples the solid angle an area light subtends at point p.
LightSample sample_area_light(const AreaLight& light, const Vec3& p, Float u1, Float u2);
// The density of that sampling for the direction towards `on_light` (a point found by a
// ray from p) with emitting-surface normal n_light.
Float area_light_pdf(const AreaLight& light, const Vec3& p, const Vec3& on_light,
                     const Vec3& n_light);
// Radiance leaving the light at a surface point with outward normal n towards w.
Color area_light_radiance(const AreaLight& light, const Vec3& n, const Vec3& w);

// Spectral mode: a light's emission at the wavelengths w (for an area light, where it
// emits at all; area_light_radiance tells where).
SampledSpectrum emission_spectrum(const std::optional<Spectrum>& spectrum, const Color& rgb, const SampledWavelengths& w);
SampledSpectrum area_light_spectrum(const AreaLight& light, const SampledWavelengths& w);

}  // namespace gonio::render
