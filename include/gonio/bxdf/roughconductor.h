#pragma once
// Rough conductor: the Cook–Torrance / Torrance–Sparrow microfacet BRDF
//   f = D(wh) G2(wo, wi) F(wo·wh) / (4 |cos θo| |cos θi|),  wh = normalize(wo + wi)
// (Cook & Torrance 1982; Walter et al. 2007, eq. 20), with the exact conductor Fresnel
// (or Schlick's), height-correlated G2 and visible-normal sampling. Two-sided
// (SPEC §1). Below MicrofacetDistribution::kSmoothAlpha it is the smooth conductor.
// Optionally with Kulla & Conty's (2017) multiple-scattering lobe (multiscatter.h).

#include <optional>
#include <string_view>

#include "gonio/bxdf/conductor.h"
#include "gonio/bxdf/contract.h"
#include "gonio/microfacet.h"
#include "gonio/multiscatter.h"

namespace gonio {

template <typename C>
struct RoughConductorBxDFT {
  using color_type = C;
  static constexpr std::string_view kName = "roughconductor";
  MicrofacetDistribution distribution;
  ConductorFresnelT<Unpolarized<C>> fresnel;
  // Kulla–Conty energy compensation; absent = single scattering only. It depolarizes.
  std::optional<MultiscatterLobeT<Unpolarized<C>>> multiscatter;

  BxDFFlags flags() const {
    return distribution.effectively_smooth() ? BxDFFlags::SpecularReflection : BxDFFlags::GlossyReflection;
  }
  bool is_isotropic() const { return distribution.is_isotropic(); }

  // Directions this close to the tangent plane are fully shadowed (G → 0); treating
  // them as such keeps products of cosines from underflowing into infinities.
  static bool grazing(const Vec3& w) { return std::abs(w.z) < Float(1e-7); }

  BSDFEvalT<C> eval(Vec3 wo, Vec3 wi, TransportMode = TransportMode::Radiance) const {
    if ((wo.z > 0) != (wi.z > 0) || grazing(wo) || grazing(wi) || distribution.effectively_smooth()) return {};
    const Vec3 wo_actual = wo, wi_actual = wi;  // for the polarization frames
    if (wo.z < 0) {
      wo.z = -wo.z;
      wi.z = -wi.z;
    }
    // wm = h/|h|, h = wo + wi; D from h itself (D_unnormalized), so that sample() can
    // give the same number for the pair it returns.
    const Vec3 h = wo + wi;
    const Float h2 = length_squared(h);
    if (h2 == 0) return {};
    const Float D = distribution.D_unnormalized(h, h2);
    const Float to = distribution.smith_t(wo), ti = distribution.smith_t(wi);
    // wo·wm = wi·wm = |wo + wi|/2 for unit wo, wi: symmetric in the pair, and free of the
    // cancellation in dot(wo, h) = 1 + wo·wi at grazing.
    const Float cos_h = std::min(std::sqrt(h2) / 2, Float(1));
    const C F = fresnel_factor<C>(fresnel(cos_h, std::min(h2 / 4, Float(1))), [&] { return fresnel.mueller(cos_h); },
                                  wo_actual, wi_actual);
    // G2 / (4 cos θo cos θi) = 1 / (2 (cos θi T(wo) + cos θo T(wi))) (smith_t).
    C f = F * (D / (2 * (wi.z * to + wo.z * ti)));
    // Visible-normal density of wm, times the Jacobian dωm/dωi = 1/(4 wo·wm):
    // D / (4 cos θo (1 + Λo)) = D / (2 (T(wo) + cos θo)).
    Float pdf = D / (2 * (to + wo.z));
    if (multiscatter) {
      const Float eo = multiscatter->E(wo), ei = multiscatter->E(wi);
      f += multiscatter->f(eo, ei);
      pdf = multiscatter->mix_pdf(eo, pdf, wi.z, ei);
    }
    return {f, pdf};
  }
  C f(const Vec3& wo, const Vec3& wi, TransportMode mode = TransportMode::Radiance) const {
    return eval(wo, wi, mode).f;
  }
  Float pdf(Vec3 wo, Vec3 wi, TransportMode = TransportMode::Radiance) const {
    if ((wo.z > 0) != (wi.z > 0) || grazing(wo) || grazing(wi) || distribution.effectively_smooth()) return 0;
    if (wo.z < 0) {
      wo.z = -wo.z;
      wi.z = -wi.z;
    }
    const Vec3 h = wo + wi;
    const Float h2 = length_squared(h);
    if (h2 == 0) return 0;
    const Float p = distribution.D_unnormalized(h, h2) / (2 * (distribution.smith_t(wo) + wo.z));  // as in eval
    return multiscatter ? multiscatter->mix_pdf(multiscatter->E(wo), p, wi.z, multiscatter->E(wi)) : p;
  }

  std::optional<BSDFSampleT<C>> sample(Vec3 wo, Float u_lobe, Float u1, Float u2,
                                   TransportMode mode = TransportMode::Radiance) const {
    if (wo.z == 0 || (grazing(wo) && !distribution.effectively_smooth())) return std::nullopt;
    const bool flip = wo.z < 0;
    if (flip) wo.z = -wo.z;
    if (distribution.effectively_smooth()) {
      const Vec3 wi{-wo.x, -wo.y, flip ? -wo.z : wo.z};
      const C F = fresnel_factor<C>(fresnel(wo.z), [&] { return fresnel.mueller(wo.z); },
                                    Vec3{wo.x, wo.y, wi.z}, wi);
      return BSDFSampleT<C>{wi, F, 1, true, Lobe::Reflection, 1};
    }
    if (multiscatter) {
      // Mixture of the single-scattering lobe and the multiple-scattering one, the latter
      // drawn ∝ (1 − E(μi)) μi; the weight is f |cos θi| / pdf of the mixture, at most the
      // larger of the two lobes' own weights over their selection probabilities.
      const Vec3 wi = u_lobe < multiscatter->probability(multiscatter->E(wo)) ? multiscatter->sample(u1, u2)
                                                               : reflect(wo, distribution.sample_visible(wo, u1, u2));
      if (!(wi.z > 0) || grazing(wi)) return std::nullopt;
      const BSDFEvalT<C> e = eval(wo, wi, mode);
      if (!(e.pdf > 0)) return std::nullopt;
      return BSDFSampleT<C>{{wi.x, wi.y, flip ? -wi.z : wi.z}, e.f * (wi.z / e.pdf), e.pdf, false, Lobe::Reflection, 1};
    }
    return distribution.type == MicrofacetType::GGX
               ? sample_single<static_cast<int>(MicrofacetType::GGX)>(wo, flip, u1, u2)
               : sample_single<static_cast<int>(MicrofacetType::Beckmann)>(wo, flip, u1, u2);
  }

 private:
  // The single-scattering sample for wo.z > 0 (flip: wo was below), per distribution type.
  template <int kType>
  [[gnu::always_inline]] std::optional<BSDFSampleT<C>> sample_single(const Vec3& wo, bool flip, Float u1, Float u2) const {
    const auto vn = distribution.sample_visible_terms<kType>(wo, u1, u2);
    const Float to = distribution.smith_t<kType>(wo);  // the sampler's stretched length (CSE)
    // wi = reflect(wo, wm) = 2 (wo·wm) wm − wo (lecture §5.2) with wm = m/|m|:
    // 2 q m − wo, q = (wo·m)/|m|²; and (wo·wm)² = q (wo·m), without a sqrt.
    const Float om = dot(wo, vn.m);
    const Float q = om / vn.m2;
    const Vec3 wi = vn.m * (2 * q) - wo;
    if (!(wi.z > 0) || grazing(wi)) return std::nullopt;
    // pdf = D_wo(wm) / (4 wo·wm) = D / (4 cos θo (1 + Λo)) = D / (2 (T(wo) + cos θo)), with
    // D of the half vector of the returned pair, computed as pdf() does: for a narrow lobe
    // D(wm) is steep enough that the rounding of wi alone would move it by more than 1e-4.
    const Vec3 h = wo + wi;
    const Float h2 = length_squared(h);
    const Float pdf = distribution.D_unnormalized<kType>(h, h2) / (2 * (to + wo.z));
    if (!(pdf > 0)) return std::nullopt;
    // weight = f cos θi / pdf = F G2 / G1(wo) (Heitz & d'Eon 2014: the weight of
    // visible-normal sampling is the Fresnel term times the shadowing of wi given wo), with
    // G2/G1 in the T form of smith_t; D cancels. F is taken at the cosine eval() takes,
    // wo·wm = |wo + wi|/2 of the returned pair, not at √(q wo·m) of the sampler's normal:
    // the same number in rounding. F itself can be ill-conditioned in it: F82-tint at
    // f82 = 0, F0 = 1 touches zero at μ̄ = 1/7 (F = 1 − μ (1 − μ)⁶/(μ̄ (1 − μ̄)⁶), a double
    // root; Hoffman 2023, fresnel.h), where dF/F = 2 dμ/(μ − μ̄), so two roundings of one
    // μ gave a weight 28 % off f cos θi / pdf (issue 56).
    const Float ti = distribution.smith_t<kType>(wi);
    const Float cos_h = std::min(std::sqrt(h2) / 2, Float(1));
    const Vec3 wi_actual{wi.x, wi.y, flip ? -wi.z : wi.z};
    const C weight = fresnel_factor<C>(fresnel(cos_h, std::min(h2 / 4, Float(1))), [&] { return fresnel.mueller(cos_h); },
                                       Vec3{wo.x, wo.y, flip ? -wo.z : wo.z}, wi_actual) *
                     (wi.z * (to + wo.z) / (wi.z * to + wo.z * ti));
    return BSDFSampleT<C>{wi_actual, weight, pdf, false, Lobe::Reflection, 1};
  }
};

using RoughConductorBxDF = RoughConductorBxDFT<Color>;

}  // namespace gonio
