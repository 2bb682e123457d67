#pragma once
// Plastic: a dielectric coat (index eta) over a Lambertian base of albedo ρ, with the
// light that the coat reflects back inside accounted for (Weidlich & Wilkie 2007, §3;
// Kelemen & Szirmay-Kalos 2001, §2). The coat reflects specularly — a delta lobe F(θo)
// if smooth, the microfacet lobe D G2 F / (4 cos θo cos θi) (Walter et al. 2007, eq. 20,
// height-correlated G2) if `alpha` is given. What the coat does not reflect reaches the
// base, bounces between base and coat, and leaves:
//   f_base = ρ (1 − E(wi)) (1 − E(wo)) / (π η² (1 − ρ F_dr)),
// with E the coat's directional albedo and F_dr its diffuse reflectance seen from inside.
//   Smooth coat: E = F(θ) and F_dr = 2 ∫ F_inside(μ) μ dμ.
//   Rough coat: E = E_coat(wo), the albedo of the coat's own lobe (coat_albedo.h; the
//     smooth 1 − F would couple in energy the rough lobe never reflects, and at grazing
//     angles lose most of it), and, from the reciprocity of the coat, its hemispherical
//     transmittance from inside (1 − Ē_coat)/η², i.e. 1 − F_dr = (1 − Ē_coat)/η²
//     (Kelemen & Szirmay-Kalos 2001, §2.2, with their average albedo; the same balance as
//     Kulla & Conty 2017's 1 − E_avg).
// In both cases 1 − F_dr = (1 − Ē)/η² with Ē the coat's mean reflectance from outside, so
// the base returns (1 − E(wo)) ρ (1 − F_dr)/(1 − ρ F_dr) ≤ 1 − E(wo): with a white base
// the albedo is exactly E(wo) + 1 − E(wo) = 1 (up to the table's interpolation error).
// Reciprocal. Two-sided.

#include <cmath>
#include <optional>
#include <string_view>

#include "gonio/bxdf/contract.h"
#include "gonio/coat_albedo.h"
#include "gonio/fresnel.h"
#include "gonio/hemispherical_average.h"
#include "gonio/math/warp.h"
#include "gonio/microfacet.h"

namespace gonio {

struct PlasticBxDF {
  static constexpr std::string_view kName = "plastic";
  Color reflectance{0.5f};
  Float eta = 1.5f;
  std::optional<MicrofacetDistribution> coat;  // none: smooth coat
  // 1 − Ē: the coat's hemispherical transmittance from outside. It fixes the one from
  // inside, 1 − F_dr = (1 − Ē)/η², which is kept in that factored form: for η → 10⁴,
  // F_dr rounds to 1 in float and 1 − ρ F_dr would divide by zero.
  Float transmit_smooth = 0.9082f;  // smooth coat (set by make())
  Float transmit = 0.9082f;         // the one in use (set by update_coat())
  CoatAlbedo coat_albedo;                      // the rough coat's E_coat lookups

  static PlasticBxDF make(const Color& reflectance, Float eta, std::optional<MicrofacetDistribution> coat) {
    PlasticBxDF m;
    m.reflectance = reflectance;
    m.eta = eta;
    m.coat = coat;
    // Ē = 2 ∫ F(μ) μ dμ from outside, where F is smooth (from inside it has a kink at the
    // critical angle that Simpson's rule resolves only to ~2e-5).
    m.transmit_smooth = Float(
        1 - cosine_weighted_average([&](double mu) { return fresnel_dielectric(mu, double(eta)); }, 2048));
    if (coat) m.coat_albedo = CoatAlbedo::make(coat->type, eta);
    m.update_coat();
    return m;
  }
  // After the coat's roughness changed (a textured alpha).
  void update_coat() {
    transmit = smooth() ? transmit_smooth : 1 - coat_albedo.average(*coat);
  }

  bool smooth() const { return !coat || coat->effectively_smooth(); }
  BxDFFlags flags() const {
    return BxDFFlags::DiffuseReflection | (smooth() ? BxDFFlags::SpecularReflection : BxDFFlags::GlossyReflection);
  }
  bool is_isotropic() const { return !coat || coat->is_isotropic(); }

  // Directions this close to the tangent plane are fully shadowed for the rough coat's
  // lobe (as in the other microfacet models): it is left out there.
  static bool grazing(const Vec3& w) { return std::abs(w.z) < Float(1e-7); }

  // The coat's reflectance for w on the upper side: F (smooth) or E_coat (rough).
  Float coat_reflectance(const Vec3& w) const {
    return smooth() ? fresnel_dielectric(w.z, eta) : coat_albedo.E(*coat, w);
  }
  Color base(Float eo, Float ei) const {
    const Float t = (1 - ei) * (1 - eo);
    // ρ / (η² (1 − ρ F_dr)) = ρ / ((1 − ρ) η² + ρ (1 − Ē)).
    return map(reflectance, [&](Float r) { return r / ((1 - r) * eta * eta + r * transmit); }) * (t * kInvPi);
  }
  // Probability of sampling the coat's lobe rather than the base, by expected energy.
  Float coat_probability(const Vec3& wo, Float eo) const {
    if (!smooth() && grazing(wo)) return 0;
    const Float b = (1 - eo) * reflectance.average();
    return eo + b > 0 ? eo / (eo + b) : Float(1);
  }

  BSDFEval eval(Vec3 wo, Vec3 wi, TransportMode = TransportMode::Radiance) const {
    if (!(wo.z * wi.z > 0)) return {};
    if (wo.z < 0) {
      wo.z = -wo.z;
      wi.z = -wi.z;
    }
    if (!smooth()) return eval_rough(wo, wi);
    // Smooth coat: the base alone (the mirror lobe is a delta), kept small so that it
    // inlines into the callers' loops.
    const Float eo = fresnel_dielectric(wo.z, eta);
    const Float pc = coat_probability(wo, eo);
    return {base(eo, fresnel_dielectric(wi.z, eta)), (1 - pc) * wi.z * kInvPi};
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
    const Float pc = coat_probability(wo, coat_reflectance(wo));
    Vec3 wi;
    if (u_lobe < pc) {
      if (smooth()) {
        // The coat's mirror reflection: weight F / P.
        const Float F = fresnel_dielectric(wo.z, eta);
        return BSDFSample{{-wo.x, -wo.y, flip ? -wo.z : wo.z}, Color(F / pc), pc, true, Lobe::Reflection, 1};
      }
      wi = reflect(wo, coat->sample_visible(wo, u1, u2));
      if (grazing(wi)) return std::nullopt;  // the coat lobe is 0 there
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

  // The rough coat for wo.z, wi.z > 0: base coupled through E_coat, plus the coat's lobe.
  [[gnu::noinline]] BSDFEval eval_rough(const Vec3& wo, const Vec3& wi) const {
    const Float eo = coat_albedo.E(*coat, wo);
    Color f = base(eo, coat_albedo.E(*coat, wi));
    const Float pc = coat_probability(wo, eo);
    Float pdf = (1 - pc) * wi.z * kInvPi;
    if (!grazing(wo) && !grazing(wi)) {
      const Vec3 h = wo + wi;
      const Float h2 = length_squared(h);
      const Float D = coat->D_unnormalized(h, h2);
      const Float to = coat->smith_t(wo), ti = coat->smith_t(wi);
      // F at wo·wm = |wo + wi|/2 (symmetric in the pair); with T = smith_t,
      // G2 / (4 cos θo cos θi) = 1 / (2 (cos θi T(wo) + cos θo T(wi))): no product of
      // cosines that could underflow, no Λ that could overflow.
      const Float F = fresnel_dielectric(std::min(std::sqrt(h2) / 2, Float(1)), eta);
      f += Color(D * F / (2 * (wi.z * to + wo.z * ti)));
      // Visible-normal density times dωm/dωi: D / (4 cos θo (1 + Λo)) = D / (2 (T(wo) + cos θo)).
      pdf += pc * D / (2 * (to + wo.z));
    }
    return {f, pdf};
  }

  // Closed form for the smooth coat: F(θo) + (1 − F(θo)) ρ (1 − F_dr) / (1 − ρ F_dr).
  std::optional<DirectionalAlbedo> albedo(const Vec3& wo, TransportMode = TransportMode::Radiance) const {
    if (!smooth()) return std::nullopt;
    if (wo.z == 0) return DirectionalAlbedo{};
    const Float F = fresnel_dielectric(std::abs(wo.z), eta);
    const Color b = map(reflectance, [&](Float r) { return r * transmit / ((1 - r) * eta * eta + r * transmit); });
    return DirectionalAlbedo{Color(F) + b * (1 - F), Color{}};
  }
};

}  // namespace gonio
