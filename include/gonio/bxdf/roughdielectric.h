#pragma once
// Rough dielectric interface: microfacet reflection and refraction of Walter, Marschner,
// Li & Torrance 2007, "Microfacet Models for Refraction through Rough Surfaces":
// generalized half vector h ∝ n_i wi + n_o wo (eq. 16), reflection
//   f_r = D G2 F / (4 |cos θo| |cos θi|)                                   (eq. 20)
// and transmission (radiance mode)
//   f_t = |wi·h| |wo·h| / (|cos θi| |cos θo|) · n_o² (1 − F) G2 D / (n_i wi·h + n_o wo·h)²  (eq. 21)
// with height-correlated G2 (SPEC §1), visible-normal sampling, total internal
// reflection, and the radiance scaling (n_wo/n_wi)² only in radiance mode. Below
// MicrofacetDistribution::kSmoothAlpha it is the smooth dielectric.

#include <optional>
#include <string_view>

#include "gonio/bxdf/contract.h"
#include "gonio/bxdf/dielectric.h"
#include "gonio/fresnel.h"
#include "gonio/microfacet.h"

namespace gonio {

struct RoughDielectricBxDF {
  static constexpr std::string_view kName = "roughdielectric";
  MicrofacetDistribution distribution;
  Float eta = 1.5f;  // n_inside / n_outside

  // An index-matched interface (η = 1) refracts nothing: light goes straight through,
  // a delta lobe whatever the roughness; near η = 1 the transmitted lobe is about
  // α |η − 1| wide. Once that is below the smoothness threshold the model is the smooth
  // dielectric (its reflection, F ≈ ((η−1)/(η+1))², is then negligible), as is a surface
  // below the threshold.
  bool specular() const {
    const Float alpha = std::max(distribution.alpha_x, distribution.alpha_y);
    return distribution.effectively_smooth() || alpha * std::abs(eta - 1) < MicrofacetDistribution::kSmoothAlpha;
  }

  BxDFFlags flags() const {
    return specular()
               ? BxDFFlags::SpecularReflection | BxDFFlags::SpecularTransmission
               : BxDFFlags::GlossyReflection | BxDFFlags::GlossyTransmission;
  }
  Float relative_eta() const { return eta; }

  // Directions this close to the tangent plane are fully shadowed (G → 0); treating
  // them as such keeps products of cosines from underflowing into infinities.
  static bool grazing(const Vec3& w) { return std::abs(w.z) < Float(1e-7); }
  bool is_isotropic() const { return distribution.is_isotropic(); }

  BSDFEval eval(const Vec3& wo, const Vec3& wi, TransportMode mode = TransportMode::Radiance) const {
    if (specular() || grazing(wo) || grazing(wi)) return {};
    const bool reflection = (wo.z > 0) == (wi.z > 0);
    // The half vector and every dot product are computed from the pair in a fixed order
    // (for transmission: the outside direction, then the inside one), so that f(wo, wi)
    // and f(wi, wo) use identical numbers and reciprocity holds to rounding even where
    // Fresnel is steep, at the critical angle of a microfacet.
    const Vec3& a = reflection || wo.z > 0 ? wo : wi;  // outside (or wo, for reflection)
    const Vec3& b = reflection || wo.z > 0 ? wi : wo;  // inside (or wi)
    // wm ∝ n_a a + n_b b (Walter et al. 2007, eq. 16), turned to the outside.
    Vec3 wm = reflection ? a + b : a + b * eta;
    if (length_squared(wm) == 0) return {};
    wm = normalize(wm);
    if (wm.z < 0) wm = -wm;
    const Float dot_a = dot(a, wm), dot_b = dot(b, wm);
    // Microfacets seen from behind by either direction contribute nothing.
    if (dot_a * a.z <= 0 || dot_b * b.z <= 0) return {};
    const Float D = distribution.D(wm);
    const Float lo = distribution.Lambda(wo), li = distribution.Lambda(wi);
    const Float G2 = 1 / (1 + lo + li);
    const Float dot_o = reflection || wo.z > 0 ? dot_a : dot_b;
    // D_wo(wm) = G1(wo) |wo·wm| D / |cos θo|
    const Float d_vis = D * std::abs(dot_o) / ((1 + lo) * std::abs(wo.z));
    if (reflection) {
      // F at the mean of the two (equal) cosines: symmetric in wo and wi.
      const Float F = fresnel_dielectric((dot_a + dot_b) / 2, eta);
      const Float f = D * G2 * F / (4 * std::abs(wo.z * wi.z));
      return {Color(f), d_vis / (4 * std::abs(dot_o)) * F};
    }
    // Fresnel is the same from both sides of a refraction; take it from the outside.
    const Float F = fresnel_dielectric(dot_a, eta);
    const Float s = dot_a + eta * dot_b;  // n_a (a·wm) + n_b (b·wm)
    const Float S = s * s;
    if (!(S > 0)) return {};
    // Eq. 21 in radiance mode, with wo outside (n_wo = 1, n_wi = η):
    //   f = D G2 (1 − F) |a·wm| |b·wm| / (|cos θa| |cos θb| S);
    // with wo inside it is η² times that (the generalized reciprocity of SPEC §1).
    // Importance mode differs by (n_wi/n_wo)².
    const Float base = D * G2 * (1 - F) * std::abs(dot_a * dot_b / (S * a.z * b.z));
    const Float eta_crossed = wo.z > 0 ? eta : 1 / eta;  // n_wi / n_wo
    const Float f = base * (wo.z > 0 ? Float(1) : eta * eta) * (mode == TransportMode::Radiance ? Float(1) : eta_crossed * eta_crossed);
    // dωm/dωi = n_wi² |wi·wm| / S
    const Float n_wi2 = wo.z > 0 ? eta * eta : Float(1);
    const Float dwm_dwi = n_wi2 * std::abs(wo.z > 0 ? dot_b : dot_a) / S;
    return {Color(f), d_vis * dwm_dwi * (1 - F)};
  }
  Color f(const Vec3& wo, const Vec3& wi, TransportMode mode = TransportMode::Radiance) const {
    return eval(wo, wi, mode).f;
  }
  Float pdf(const Vec3& wo, const Vec3& wi, TransportMode mode = TransportMode::Radiance) const {
    return eval(wo, wi, mode).pdf;
  }

  std::optional<BSDFSample> sample(const Vec3& wo, Float u_lobe, Float u1, Float u2,
                                   TransportMode mode = TransportMode::Radiance) const {
    if (specular()) return DielectricBxDF{eta}.sample(wo, u_lobe, u1, u2, mode);
    if (grazing(wo)) return std::nullopt;
    // Normals visible from wo; from inside, those visible from −wo (the same
    // distribution, as D_w uses |w·wm|).
    const Vec3 wm = distribution.sample_visible(wo.z > 0 ? wo : -wo, u1, u2);
    const Float F = fresnel_dielectric(dot(wo, wm), eta);
    Vec3 wi;
    Lobe lobe;
    Float eta_crossed = 1;
    if (u_lobe < F) {
      wi = reflect(wo, wm);
      if (!(wo.z * wi.z > 0)) return std::nullopt;
      lobe = Lobe::Reflection;
    } else {
      const auto r = refract(wo, wm, eta);
      if (!r || !(wo.z * r->wt.z < 0)) return std::nullopt;
      wi = r->wt;
      eta_crossed = r->eta;
      lobe = Lobe::Transmission;
    }
    // f and pdf from eval, so that the sample agrees with f() and pdf() exactly.
    const BSDFEval e = eval(wo, wi, mode);
    if (!(e.pdf > 0)) return std::nullopt;
    return BSDFSample{wi, e.f * (std::abs(wi.z) / e.pdf), e.pdf, false, lobe, eta_crossed};
  }
};

}  // namespace gonio
