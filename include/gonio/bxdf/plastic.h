#pragma once
// Plastic: a dielectric coat (index eta) over a Lambertian base of albedo ρ, with the
// light that the coat reflects back inside accounted for (Weidlich & Wilkie 2007, §3;
// Kelemen & Szirmay-Kalos 2001). The coat reflects F(θo) specularly — a delta lobe if
// smooth, a microfacet lobe D G2 F / (4 cos θo cos θi) if `alpha` is given. Light
// refracted in reaches the base, bounces between base and coat, and leaves:
//   f_base = (1 − F(θi)) (1 − F(θo)) ρ / (π η² (1 − ρ F_dr)),
// F_dr the coat's diffuse reflectance seen from inside (2 ∫ F μ dμ). Since
// 1 − F_dr = (1 − F_dr,outside)/η², the base returns (1 − F(θo)) ρ(1 − F_dr)/(1 − ρ F_dr)
// ≤ 1 − F(θo): energy is conserved by construction. Reciprocal. Two-sided.

#include <cmath>
#include <optional>
#include <string_view>

#include "gonio/bxdf/contract.h"
#include "gonio/fresnel.h"
#include "gonio/math/warp.h"
#include "gonio/microfacet.h"

namespace gonio {

struct PlasticBxDF {
  static constexpr std::string_view kName = "plastic";
  Color reflectance{0.5f};
  Float eta = 1.5f;
  std::optional<MicrofacetDistribution> coat;  // none: smooth coat
  Float fdr_inside = 0.596345f;                // set by make()

  static PlasticBxDF make(const Color& reflectance, Float eta, std::optional<MicrofacetDistribution> coat) {
    PlasticBxDF m{reflectance, eta, coat, 0};
    // F_dr = 2 ∫ F(μ) μ dμ for light inside the coat, composite Simpson (the kink at the
    // critical angle costs ~1e-7 at this resolution).
    constexpr int n = 2048;
    double acc = 0;
    for (int i = 0; i <= n; ++i) {
      const double mu = double(i) / n, w = (i == 0 || i == n) ? 1 : (i % 2 ? 4 : 2);
      acc += w * 2 * mu * fresnel_dielectric(-mu, double(eta));
    }
    m.fdr_inside = Float(acc / (3 * n));
    return m;
  }

  bool smooth() const { return !coat || coat->effectively_smooth(); }
  BxDFFlags flags() const {
    return BxDFFlags::DiffuseReflection | (smooth() ? BxDFFlags::SpecularReflection : BxDFFlags::GlossyReflection);
  }
  bool is_isotropic() const { return !coat || coat->is_isotropic(); }

  Color base(Float cos_o, Float cos_i) const {
    const Float t = (1 - fresnel_dielectric(cos_i, eta)) * (1 - fresnel_dielectric(cos_o, eta));
    return map(reflectance, [&](Float r) { return r / (1 - r * fdr_inside); }) * (t * kInvPi / (eta * eta));
  }
  // Probability of sampling the coat's lobe rather than the base, by expected energy.
  Float coat_probability(Float cos_o) const {
    const Float F = fresnel_dielectric(cos_o, eta);
    const Float b = (1 - F) * reflectance.average();
    return F + b > 0 ? F / (F + b) : Float(1);
  }

  BSDFEval eval(Vec3 wo, Vec3 wi, TransportMode = TransportMode::Radiance) const {
    if (!(wo.z * wi.z > 0)) return {};
    if (wo.z < 0) {
      wo.z = -wo.z;
      wi.z = -wi.z;
    }
    Color f = base(wo.z, wi.z);
    const Float pc = coat_probability(wo.z);
    Float pdf = (1 - pc) * wi.z * kInvPi;
    if (!smooth()) {
      const Vec3 wm = normalize(wo + wi);
      const Float lo = coat->Lambda(wo), li = coat->Lambda(wi), D = coat->D(wm);
      const Float F = fresnel_dielectric(dot(wo, wm), eta);
      f += Color(D * F / ((1 + lo + li) * 4 * wo.z * wi.z));
      pdf += pc * D / (4 * wo.z * (1 + lo));
    }
    return {f, pdf};
  }
  Color f(const Vec3& wo, const Vec3& wi, TransportMode mode = TransportMode::Radiance) const {
    return eval(wo, wi, mode).f;
  }
  Float pdf(const Vec3& wo, const Vec3& wi, TransportMode mode = TransportMode::Radiance) const {
    return eval(wo, wi, mode).pdf;
  }

  std::optional<BSDFSample> sample(Vec3 wo, Float u_lobe, Float u1, Float u2,
                                   TransportMode mode = TransportMode::Radiance) const {
    if (wo.z == 0) return std::nullopt;
    const bool flip = wo.z < 0;
    if (flip) wo.z = -wo.z;
    const Float pc = coat_probability(wo.z);
    Vec3 wi;
    if (u_lobe < pc) {
      if (smooth()) {
        // The coat's mirror reflection: weight F / P.
        const Float F = fresnel_dielectric(wo.z, eta);
        return BSDFSample{{-wo.x, -wo.y, flip ? -wo.z : wo.z}, Color(F / pc), pc, true, Lobe::Reflection, 1};
      }
      wi = reflect(wo, coat->sample_visible(wo, u1, u2));
    } else {
      wi = square_to_cosine_hemisphere(u1, u2);
    }
    if (!(wi.z > 0)) return std::nullopt;
    const BSDFEval e = eval(wo, wi, mode);
    if (!(e.pdf > 0)) return std::nullopt;
    const Color weight = e.f * (wi.z / e.pdf);
    if (flip) wi.z = -wi.z;
    return BSDFSample{wi, weight, e.pdf, false, Lobe::Reflection, 1};
  }

  // Closed form for the smooth coat: F(θo) + (1 − F(θo)) ρ (1 − F_dr) / (1 − ρ F_dr).
  std::optional<DirectionalAlbedo> albedo(const Vec3& wo, TransportMode = TransportMode::Radiance) const {
    if (!smooth()) return std::nullopt;
    if (wo.z == 0) return DirectionalAlbedo{};
    const Float F = fresnel_dielectric(std::abs(wo.z), eta);
    const Color b = map(reflectance, [&](Float r) { return r * (1 - fdr_inside) / (1 - r * fdr_inside); });
    return DirectionalAlbedo{Color(F) + b * (1 - F), Color{}};
  }
};

}  // namespace gonio
