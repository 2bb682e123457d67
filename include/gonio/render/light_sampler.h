#pragma once
// Which light a next-event estimate samples (scene "render": {"light_sampler": ...},
// `gonio render --light-sampler`; docs/scene-format.md, "Light selection"). The choice is
// among the sampled lights — the area lights and the environment; point lights are not
// chosen, they are summed over exactly at every vertex (lecture eq. 2, path_tracer.h).
// - "bvh" (the default): a light BVH (Conty Estevez & Kulla 2018, "Importance sampling
//   of many lights with adaptive tree splitting", §4; as pbrt-v4's BVHLightSampler, PBR
//   4th ed. §12.6.3): each node bounds its lights' emitters (a box), their power and the
//   cone of their normals; one descent from the root picks a child with probability
//   proportional to its importance at the shading point (power, orientation cone,
//   distance, and the receiver's cosine bound; by power where both children's importance
//   is 0), so the light is chosen with the product of those probabilities, which pmf()
//   recomputes for MIS, and the pmf over all lights sums to 1. The environment takes a
//   fixed share kEnvironmentShare of the choices (1 when it is the only sampled light).
// - "power": probability proportional to each light's emitted power (light_power), from
//   a CDF made once per scene; the environment among them by its estimate.
// - "uniform": every sampled light alike (the renderer's choice before issue 38).
// The pmf a strategy reports for a light is exactly the probability with which sample()
// returns it at that point (the MIS weights need the selection's own density). Sampling
// and pmf() allocate nothing and call nothing virtual.

#include <cstdint>
#include <optional>
#include <string_view>
#include <vector>

#include "gonio/math/vec3.h"
#include "gonio/render/lights.h"

namespace gonio::render {

enum class LightSamplerType : std::uint8_t { Bvh, Power, Uniform };

// "bvh", "power", "uniform"; nullopt for any other name.
std::optional<LightSamplerType> light_sampler_type_from_name(std::string_view name);
const char* light_sampler_type_name(LightSamplerType type);

// Emitted power Φ (the flux leaving the emitter, averaged over the colour's channels), for
// the "power" strategy and the BVH's node weights:
//   point light (intensity I):           Φ = 4π I        (an isotropic source; not chosen,
//                                                          point lights are summed exactly)
//   quad light (radiance L, area A):     Φ = π L A       (a Lambertian emitter: ∫ L cos θ dω
//                                                          = π L over its hemisphere; ×2 two-sided)
//   sphere light (radiance L, radius r): Φ = π L · 4π r²
//   environment (mean radiance L̄):       Φ ≈ π L̄ · 4π R² — the power it sends through the
//                                          scene's bounding sphere of radius R: L̄ over the
//                                          sphere of directions, each through a disk π R²
//                                          (as PBR 4th ed. §12.5's Phi() of infinite lights)
Float light_power(const PointLight& light);
Float light_power(const AreaLight& light);
Float light_power(const Environment& environment, Float scene_radius);

// The bounds of a set of emitters as the BVH keeps them (Conty Estevez & Kulla 2018, §4.1):
// a box, the total power, and the cone of emission directions — normals within θo of the
// axis w, each emitting up to θe from its normal (θe = π/2 for every emitter here).
struct LightBounds {
  Vec3 lo{0, 0, 0}, hi{0, 0, 0};
  Vec3 w{0, 0, 1};
  Float phi = 0;
  Float cos_o = 1, cos_e = 0;  // cos θo, cos θe

  // Conty Estevez & Kulla 2018, eq. 3 (bounded as in §4.3): an upper bound of the light's
  // contribution to a point p with normal n (n = 0: no receiver cosine),
  //   Φ · cos θ'_i · cos θ' / d²  if θ' < θe, else 0,
  // θ' = max(0, θ − θo − θb) the smallest angle between the cone and the direction from the
  // box to p, θb the half-angle of the box's bounding sphere seen from p, and θ'_i =
  // max(0, θi − θb) for the angle θi between n (either side) and the direction to the box.
  // d² is the squared distance to the box's centre, at least (half its diagonal)².
  Float importance(const Vec3& p, const Vec3& n) const;
};

LightBounds light_bounds(const AreaLight& light);
LightBounds merge(const LightBounds& a, const LightBounds& b);

class LightSampler {
 public:
  // Conty Estevez & Kulla do not fix how the environment (unbounded) shares the choice
  // with the tree; as pbrt-v4's BVHLightSampler, it counts as much as the whole tree.
  static constexpr Float kEnvironmentShare = Float(0.5);

  // `lights`: the area lights (index i is light i); `environment`: null when it is black
  // (then never chosen); `scene_radius`: for the environment's power estimate.
  LightSampler(const std::vector<AreaLight>& lights, const Environment* environment, Float scene_radius,
               LightSamplerType type);

  struct Choice {
    int light = -1;  // an index into the area lights, environment_index() for the environment, -1: none
    Float pmf = 0;
  };
  // The light for a next-event estimate at p (normal n, used up to its sign) from one
  // uniform number u.
  Choice sample(const Vec3& p, const Vec3& n, Float u) const;
  // The probability that sample(p, n, ·) chooses `light` (an area-light index or
  // environment_index()).
  Float pmf(const Vec3& p, const Vec3& n, int light) const;

  int environment_index() const { return area_count_; }
  int count() const { return area_count_ + (has_environment_ ? 1 : 0); }
  LightSamplerType type() const { return type_; }

 private:
  struct Node {
    LightBounds bounds;
    // Interior: the children are this node + 1 and `second`; leaf: `second` is the light.
    int second = -1;
    bool leaf = false;
  };
  int build(std::vector<int>& order, int begin, int end, const std::vector<LightBounds>& bounds, int depth);
  Float area_share() const;
  Float first_child_probability(int node, const Vec3& p, const Vec3& n) const;  // the probability that the tree (not the environment) is chosen

  LightSamplerType type_;
  int area_count_ = 0;
  bool has_environment_ = false;
  // power: cdf_[i] .. cdf_[i + 1] is light i's interval of u (the environment last).
  std::vector<float> cdf_;
  // bvh: the nodes in depth-first order, and per light the path from the root to its
  // leaf, one bit per level (1: the second child), lowest bit first.
  std::vector<Node> nodes_;
  std::vector<std::uint64_t> trail_;
};

}  // namespace gonio::render
