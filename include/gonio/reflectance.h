#pragma once
// Reflectance ρ(Γi → Γr) between solid-angle domains (lecture §4, eq. 12):
//
//   ρ = (1/Ψi) ∫Γi ∫Γr f(ωi → ωr) cos θi cos θr dωi dωr,   Ψi = ∫Γi cos θi dωi,
//
// the ratio of the power leaving into Γr to the power arriving from Γi under uniform
// incident radiance. Each domain is a direction dω, a cone Ω or a hemisphere H², on
// either side of the surface (the exitant side decides between reflection and
// transmission). ρ is an energy ratio, so transmission into a denser medium is not
// scaled by η².
//
// When Γr is a single direction, ρ is infinitesimal; gonio then reports the reflectance
// factor π (1/Ψi) ∫Γi f cos θi dωi (Nicodemus et al. 1977, NBS Monograph 160, §5): the
// ratio to an ideal white diffuser under the same geometry (π f for direction–direction).
//
// Estimates are Monte Carlo with the model's own importance sampling (the model is
// sampled in importance mode from ωi, which yields ωr with weight
// f(ωi → ωr) |cos θr| / pdf), with per-channel standard errors; closed forms are used
// where the model provides an exact directional albedo.

#include <cstdint>
#include <optional>
#include <variant>

#include "gonio/bxdf.h"

namespace gonio {

struct DirectionDomain {
  Vec3 w{0, 0, 1};  // local frame; need not be unit length
};
// Directions within `half_angle` (radians, in (0, π/2]) of `axis`. The cone must not
// cross the tangent plane (polar angle of the axis + half_angle ≤ π/2).
struct ConeDomain {
  Vec3 axis{0, 0, 1};
  double half_angle = 0.5;
};
struct HemisphereDomain {
  bool upper = true;  // z > 0 (outside) or z < 0 (inside)
};
using SolidAngleDomain = std::variant<DirectionDomain, ConeDomain, HemisphereDomain>;

struct ReflectanceOptions {
  std::uint64_t samples = 1u << 20;
  std::uint64_t seed = 1;
};

struct ReflectanceEstimate {
  Color value;
  Color standard_error;  // 0 where the value is exact
  bool exact = false;
};

// Throws InputError for degenerate domains (zero direction, cone out of range).
ReflectanceEstimate reflectance(const BxDF& bxdf, const SolidAngleDomain& incident,
                                const SolidAngleDomain& exitant,
                                const ReflectanceOptions& options = {});

// SPEC §3 `gonio albedo`: the lecture's ρ_hd(ωo) (lecture §4) seen from the view
// direction wo: `reflectance` = ∫ f(wo, wi) cos θi dωi over wo's hemisphere and
// `transmittance` = ∫ f(wo, wi) (n_wi/n_wo)² |cos θi| dωi over the other, f in radiance
// mode with the refraction's radiance scaling removed (so a lossless interface gives 1),
// and their sum. For a reciprocal model this equals the fraction of light arriving along wo
// that is scattered (Veach 1997, §5.2: f_imp(wo, wi) = f_rad(wi, wo)); for a model that is
// not (BxDF::nonreciprocal_reason(), e.g. OpenPBR's view-dependent coat and fuzz) that
// light-side figure differs and follows in `light` (importance mode).
// For either colour mode: an RGB model (BxDF) or a spectral one (SpectralBxDF, e.g. at
// one wavelength, `gonio albedo --wavelength`).
template <typename C>
struct AlbedoSplitT {
  C reflectance, transmittance, albedo;
  C se_reflectance, se_transmittance, se_albedo;
};
template <typename C>
struct AlbedoEstimateT : AlbedoSplitT<C> {
  bool exact = false;
  // The light-side figures, for a model that is not reciprocal only.
  std::optional<AlbedoSplitT<C>> light;
};
using AlbedoEstimate = AlbedoEstimateT<Color>;

// The albedo at θ = 90° exactly is reported as its limit θ → 90°: wo is taken at
// |cos θ| = kGrazingAlbedoCosine. At cos θ = 0 models differ in what they return for a
// direction in the tangent plane (0 from a rough conductor, whose masking vanishes, F = 1
// from a smooth one), while every albedo is continuous in θ up to the limit.
inline constexpr Float kGrazingAlbedoCosine = Float(1e-5);

// ρ_hd(ωo) of the view direction wo (and, for a non-reciprocal model, the light's).
template <typename C>
AlbedoEstimateT<C> directional_albedo(const BxDFT<C>& bxdf, const Vec3& wo, const ReflectanceOptions& options = {});

// ρ_hh: the cosine-weighted average of directional_albedo over every wo on one side.
template <typename C>
AlbedoEstimateT<C> hemispherical_albedo(const BxDFT<C>& bxdf, bool inside, const ReflectanceOptions& options = {});

// Instantiated in src/reflectance.cpp for both modes.
extern template AlbedoEstimateT<Color> directional_albedo(const BxDF&, const Vec3&, const ReflectanceOptions&);
extern template AlbedoEstimateT<SampledSpectrum> directional_albedo(const SpectralBxDF&, const Vec3&,
                                                                    const ReflectanceOptions&);
extern template AlbedoEstimateT<Color> hemispherical_albedo(const BxDF&, bool, const ReflectanceOptions&);
extern template AlbedoEstimateT<SampledSpectrum> hemispherical_albedo(const SpectralBxDF&, bool,
                                                                      const ReflectanceOptions&);

}  // namespace gonio
