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

struct RoughConductorBxDF {
  static constexpr std::string_view kName = "roughconductor";
  MicrofacetDistribution distribution;
  ConductorFresnel fresnel;
  // Kulla–Conty energy compensation; absent = single scattering only.
  std::optional<MultiscatterLobe> multiscatter;

  BxDFFlags flags() const {
    return distribution.effectively_smooth() ? BxDFFlags::SpecularReflection : BxDFFlags::GlossyReflection;
  }
  bool is_isotropic() const { return distribution.is_isotropic(); }

  // Directions this close to the tangent plane are fully shadowed (G → 0); treating
  // them as such keeps products of cosines from underflowing into infinities.
  static bool grazing(const Vec3& w) { return std::abs(w.z) < Float(1e-7); }

  BSDFEval eval(Vec3 wo, Vec3 wi, TransportMode = TransportMode::Radiance) const {
    if ((wo.z > 0) != (wi.z > 0) || grazing(wo) || grazing(wi) || distribution.effectively_smooth()) return {};
    if (wo.z < 0) {
      wo.z = -wo.z;
      wi.z = -wi.z;
    }
    const Vec3 h = wo + wi;
    if (length_squared(h) == 0) return {};
    const Vec3 wm = normalize(h);
    const Float D = distribution.D(wm);
    const Float lo = distribution.Lambda(wo), li = distribution.Lambda(wi);
    const Float cos_om = std::max(Float(0), dot(wo, wm));
    const Color F = fresnel(cos_om);
    Color f = F * (D / ((1 + lo + li) * 4 * wo.z * wi.z));
    // Visible-normal density of wm, times the Jacobian dωm/dωi = 1/(4 wo·wm).
    Float pdf = D / (4 * wo.z * (1 + lo));
    if (multiscatter) {
      f += multiscatter->f(wo.z, wi.z);
      pdf = multiscatter->mix_pdf(wo.z, pdf, wi.z);
    }
    return {f, pdf};
  }
  Color f(const Vec3& wo, const Vec3& wi, TransportMode mode = TransportMode::Radiance) const {
    return eval(wo, wi, mode).f;
  }
  Float pdf(Vec3 wo, Vec3 wi, TransportMode = TransportMode::Radiance) const {
    if ((wo.z > 0) != (wi.z > 0) || grazing(wo) || grazing(wi) || distribution.effectively_smooth()) return 0;
    if (wo.z < 0) {
      wo.z = -wo.z;
      wi.z = -wi.z;
    }
    const Vec3 h = wo + wi;
    if (length_squared(h) == 0) return 0;
    const Vec3 wm = normalize(h);
    const Float p = distribution.D(wm) / (4 * wo.z * (1 + distribution.Lambda(wo)));
    return multiscatter ? multiscatter->mix_pdf(wo.z, p, wi.z) : p;
  }

  std::optional<BSDFSample> sample(Vec3 wo, Float u_lobe, Float u1, Float u2,
                                   TransportMode mode = TransportMode::Radiance) const {
    if (wo.z == 0 || (grazing(wo) && !distribution.effectively_smooth())) return std::nullopt;
    const bool flip = wo.z < 0;
    if (flip) wo.z = -wo.z;
    if (distribution.effectively_smooth()) {
      return BSDFSample{{-wo.x, -wo.y, flip ? -wo.z : wo.z}, fresnel(wo.z), 1, true, Lobe::Reflection, 1};
    }
    if (multiscatter) {
      // Mixture of the single-scattering lobe and the multiple-scattering one; the
      // weight is then f |cos θi| / pdf of the mixture.
      const Vec3 wi = u_lobe < multiscatter->probability(wo.z) ? multiscatter->sample(u1, u2)
                                                               : reflect(wo, distribution.sample_visible(wo, u1, u2));
      if (!(wi.z > 0) || grazing(wi)) return std::nullopt;
      const BSDFEval e = eval(wo, wi, mode);
      if (!(e.pdf > 0)) return std::nullopt;
      return BSDFSample{{wi.x, wi.y, flip ? -wi.z : wi.z}, e.f * (wi.z / e.pdf), e.pdf, false, Lobe::Reflection, 1};
    }
    const Vec3 wm = distribution.sample_visible(wo, u1, u2);
    const Vec3 wi = reflect(wo, wm);
    if (!(wi.z > 0) || grazing(wi)) return std::nullopt;
    // Closed forms: pdf = D_wo(wm) / (4 wo·wm) = D / (4 cos θo (1 + Λo)) and
    // weight = f cos θi / pdf = F G2 / G1(wo) = F (1 + Λo) / (1 + Λo + Λi).
    const Float lo = distribution.Lambda(wo), li = distribution.Lambda(wi);
    const Float pdf = distribution.D(wm) / (4 * wo.z * (1 + lo));
    if (!(pdf > 0)) return std::nullopt;
    const Color weight = fresnel(dot(wo, wm)) * ((1 + lo) / (1 + lo + li));
    return BSDFSample{{wi.x, wi.y, flip ? -wi.z : wi.z}, weight, pdf, false, Lobe::Reflection, 1};
  }
};

}  // namespace gonio
