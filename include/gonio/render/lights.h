#pragma once
// Light sources. Point lights are summed over exactly, the lecture's eq. 2
// (L = Σ f · I/r² · cos θ); area lights and the environment are integrated as eq. 1 by
// sampling them (next-event estimation) and by following BSDF samples that hit them,
// combined with multiple importance sampling.

#include <variant>
#include <vector>

#include "gonio/color.h"
#include "gonio/math/frame.h"
#include "gonio/math/vec3.h"
#include "gonio/math/warp.h"
#include "gonio/render/image.h"

namespace gonio::render {

// Isotropic point source of radiant intensity I (W/sr).
struct PointLight {
  Vec3 position;
  Color intensity{1};
};

// Parallelogram corner + s·edge1 + t·edge2, emitting radiance L from the side its normal
// edge1 × edge2 points to (both sides when two_sided).
struct QuadLight {
  Vec3 corner, edge1{1, 0, 0}, edge2{0, 0, 1};
  Color radiance{1};
  bool two_sided = false;

  Vec3 normal() const { return normalize(cross(edge1, edge2)); }
  Float area() const { return length(cross(edge1, edge2)); }
};

// Sphere emitting radiance L outwards, uniformly.
struct SphereLight {
  Vec3 center;
  Float radius = 1;
  Color radiance{1};
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
  explicit Environment(Color radiance) : constant_(radiance) {}
  Environment(Image map, Float scale, Float rotation_deg);

  bool is_black() const { return map_.width() == 0 && constant_.is_black(); }
  Color radiance(const Vec3& dir) const;
  LightSample sample(Float u1, Float u2) const;
  Float pdf(const Vec3& dir) const;

 private:
  Color constant_;
  Image map_;
  Float scale_ = 1, rotation_ = 0;
  // Piecewise-constant 2-D distribution over the map's pixels (rows then columns).
  std::vector<Float> row_cdf_, col_cdf_;  // row_cdf_: height+1; col_cdf_: height×(width+1)
  Float total_ = 0;
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

}  // namespace gonio::render
