#pragma once
// The BxDF contract (SPEC §1): what every reflection model provides and returns.
//
// A model is a small value type with, in the local shading frame (z = N, x = S, y = T;
// both directions unit length and pointing away from the surface):
//   Color f(wo, wi, mode)            BSDF value in 1/sr, no cosine; 0 for delta lobes
//   Float pdf(wo, wi, mode)          density per solid angle with which sample() yields wi
//   optional<BSDFSample> sample(wo, u_lobe, u1, u2, mode)
//   BxDFFlags flags()                which lobes the model has
// and may add `relative_eta()` (relative index, 1 if it does not refract), `albedo(wo, mode)`
// (exact directional albedo when a closed form exists) and `is_isotropic()`.
// The checks of the validator hold for every model that satisfies the BxDFModel concept.
//
// Directions exactly in the tangent plane (cos θo = 0) belong to neither side; a model
// returns f = 0, pdf = 0 and no sample for them, which keeps f reciprocal and sample
// consistent with pdf at grazing.

#include <concepts>
#include <cstdint>
#include <optional>

#include "gonio/color.h"
#include "gonio/math/vec3.h"

namespace gonio {

// Radiance: the BSDF as it transports radiance from wi to wo (camera paths). Importance:
// its adjoint, f_imp(wo, wi) = f_rad(wi, wo) (light paths; Veach 1997, §3.7 and §5.2).
enum class TransportMode : std::uint8_t { Radiance, Importance };

enum class BxDFFlags : std::uint8_t {
  None = 0,
  Reflection = 1 << 0,
  Transmission = 1 << 1,
  Diffuse = 1 << 2,
  Glossy = 1 << 3,
  Specular = 1 << 4,
  DiffuseReflection = Diffuse | Reflection,
  DiffuseTransmission = Diffuse | Transmission,
  GlossyReflection = Glossy | Reflection,
  GlossyTransmission = Glossy | Transmission,
  SpecularReflection = Specular | Reflection,
  SpecularTransmission = Specular | Transmission,
};
constexpr BxDFFlags operator|(BxDFFlags a, BxDFFlags b) {
  return static_cast<BxDFFlags>(static_cast<std::uint8_t>(a) | static_cast<std::uint8_t>(b));
}
constexpr BxDFFlags operator&(BxDFFlags a, BxDFFlags b) {
  return static_cast<BxDFFlags>(static_cast<std::uint8_t>(a) & static_cast<std::uint8_t>(b));
}
constexpr bool has(BxDFFlags set, BxDFFlags bits) { return (set & bits) != BxDFFlags::None; }
constexpr bool is_reflective(BxDFFlags f) { return has(f, BxDFFlags::Reflection); }
constexpr bool is_transmissive(BxDFFlags f) { return has(f, BxDFFlags::Transmission); }
constexpr bool is_specular(BxDFFlags f) { return has(f, BxDFFlags::Specular); }
// True when every lobe is a delta lobe (nothing to evaluate, only to sample).
constexpr bool is_delta_only(BxDFFlags f) {
  return is_specular(f) && !has(f, BxDFFlags::Diffuse | BxDFFlags::Glossy);
}

enum class Lobe : std::uint8_t { Reflection, Transmission };

// The result of sample(). `weight` = f · |cos θi| / pdf (for a delta lobe the limit of
// that ratio, already divided by the probability of choosing the lobe). For a delta
// sample `pdf` holds that discrete probability; SPEC §3 prints it as null.
template <typename C>
struct BSDFSampleT {
  Vec3 wi;
  C weight;
  Float pdf = 0;
  bool delta = false;
  Lobe lobe = Lobe::Reflection;
  // Relative index n(wi side) / n(wo side) crossed by a transmission; 1 for reflection.
  Float eta = 1;
};
using BSDFSample = BSDFSampleT<Color>;

// f and pdf together, for callers that need both (MIS in a renderer, `gonio eval`).
template <typename C>
struct BSDFEvalT {
  C f;
  Float pdf = 0;
};
using BSDFEval = BSDFEvalT<Color>;

// Exact directional albedo split by hemisphere, for models with a closed form. In
// importance mode this is the fraction of light arriving along wo that is reflected
// and transmitted (SPEC §3, `gonio albedo`).
template <typename C>
struct DirectionalAlbedoT {
  C reflectance;
  C transmittance;
};
using DirectionalAlbedo = DirectionalAlbedoT<Color>;

// `M::color_type` is the colour the model carries (Color or SampledSpectrum).
template <typename M>
concept BxDFModel = requires(const M& m, Vec3 w, Float u, TransportMode mode) {
  typename M::color_type;
  { m.f(w, w, mode) } -> std::same_as<typename M::color_type>;
  { m.pdf(w, w, mode) } -> std::same_as<Float>;
  { m.sample(w, u, u, u, mode) } -> std::same_as<std::optional<BSDFSampleT<typename M::color_type>>>;
  { m.flags() } -> std::same_as<BxDFFlags>;
};

// f and pdf of one model together: its own eval() where it has one (sharing the work of
// the two), else f() and pdf(). BxDFT::eval and the batch loops (batch.h) both call this.
template <BxDFModel M>
[[gnu::always_inline]] inline BSDFEvalT<typename M::color_type> model_eval(const M& m, const Vec3& wo, const Vec3& wi,
                                                                           TransportMode mode) {
  if constexpr (requires { m.eval(wo, wi, mode); }) return m.eval(wo, wi, mode);
  else return {m.f(wo, wi, mode), m.pdf(wo, wi, mode)};
}

// The factor (n_wo / n_wi)² by which a refraction scales radiance (lecture eq. 27;
// SPEC §1); `eta_crossed` = n_wi / n_wo. Importance transport carries no such factor.
inline Float transmission_scale(Float eta_crossed, TransportMode mode) {
  return mode == TransportMode::Radiance ? 1 / (eta_crossed * eta_crossed) : Float(1);
}

}  // namespace gonio
