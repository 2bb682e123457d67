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
//
// Sampling: the coat's lobe (the mirror direction, or visible normals of the rough coat,
// Heitz & d'Eon 2014) with probability P_c, else the base. A sample's weight is then at
// most the larger of the two lobes' own weights over their probabilities,
// f cos/pdf = (a + b)/(c + d) ≤ max(a/c, b/d):
//   coat  F(wo·wm) G2/G1(wo) / P_c. The visible normals that reflect above the surface
//         have wo·wm ≥ cos θo / 2 (wi.z = 2 (wo·wm) wm.z − wo.z > 0), so F(wo·wm) ≤
//         F(cos θo / 2) + F(0°)/2 (Rs falls with the angle's cosine, Rp has one minimum, at
//         Brewster's angle); P_c is kept at least a quarter of that. P_c = E_coat(wo)
//         alone gave 1/E_coat(0) = 10.8 at grazing (α = 1, η = 1.5), where F → 1 on the
//         facets seen edge-on and G2/G1 → 1, and far more for an index-matched coat
//         (η → 1: E_coat → 0, yet F → 1 on those facets).
//   base  (1 − E(wo)) (1 − E(wi)) cos θi / (π (1 − Ē) p_base(wi) (1 − P_c)) for a white
//         base. With the cosine density p_base = cos θi/π it is up to 1/(1 − Ē) (as
//         1 − P_c ≥ 1 − E(wo)), enough while the coat lets half of the light through;
//         beyond (η ≳ 6, where 1 − F peaks at Brewster's angle within 0.01° of grazing at
//         η = 10⁴, the weight was 530) the base is drawn ∝ (1 − E(μi)) μi: for the rough
//         coat exactly, from the coat tables (CoatAlbedo::sample_complement); for the
//         smooth one from an even mixture of the cosine density and
//         k / (2π ln(1 + k) (1 + k cos θi)), k = 1/cos θ_Brewster = √(1 + η²), which
//         carries the density towards Brewster's angle (weights ≤ 2.4 for η up to 10⁸).

#include <cmath>
#include <cstdint>
#include <optional>
#include <string_view>

#include "gonio/bxdf/contract.h"
#include "gonio/coat_albedo.h"
#include "gonio/fresnel.h"
#include "gonio/hemispherical_average.h"
#include "gonio/math/warp.h"
#include "gonio/microfacet.h"
#include "gonio/polarization/fresnel_factor.h"
#include "gonio/polarization/interface.h"

namespace gonio {

// What does not depend on the colour: the coat, its tables and the sampling state. The
// colour-generic model below adds the base's albedo, so that a spectral model made per
// shading point copies this part as it is.
struct PlasticCoat {
  Float eta = 1.5f;
  std::optional<MicrofacetDistribution> coat;  // none: smooth coat
  // 1 − Ē: the coat's hemispherical transmittance from outside. It fixes the one from
  // inside, 1 − F_dr = (1 − Ē)/η², which is kept in that factored form: for η → 10⁴,
  // F_dr rounds to 1 in float and 1 − ρ F_dr would divide by zero.
  Float transmit_smooth = 0.9082f;  // smooth coat (set by make())
  Float transmit = 0.9082f;         // the one in use (set by update_coat())
  CoatAlbedo coat_albedo;                      // the rough coat's E_coat lookups
  Float f0 = 0.04f;  // F at normal incidence, for the floor of the coat's probability
  // How the base is sampled (see the top of the file): by the cosine, by the mixture that
  // reaches Brewster's angle (smooth coat), or ∝ (1 − E_coat(μ)) μ (rough coat).
  enum class BaseSampling : std::uint8_t { Cosine, Brewster, Complement };
  BaseSampling base_sampling = BaseSampling::Cosine;
  Float brewster_k = 1;         // k = √(1 + η²)
  Float brewster_log = 0.693f;  // ln(1 + k)
  Float brewster_c = 0;         // k / (2π ln(1 + k)): the grazing component's density times (1 + k μ)
  Float complement_norm = 0;    // 1 / (π 2∫(1 − E_coat) μ dμ)

  static PlasticCoat make(Float eta, std::optional<MicrofacetDistribution> coat) {
    PlasticCoat m;
    m.eta = eta;
    m.coat = coat;
    // Ē = 2 ∫ F(μ) μ dμ from outside, where F is smooth (from inside it has a kink at the
    // critical angle that Simpson's rule resolves only to ~2e-5).
    m.transmit_smooth = Float(
        1 - cosine_weighted_average([&](double mu) { return fresnel_dielectric(mu, double(eta)); }, 2048));
    if (coat) m.coat_albedo = CoatAlbedo::make(coat->type, eta);
    m.f0 = fresnel_dielectric(Float(1), eta);
    const double k = std::sqrt(1 + double(eta) * double(eta));
    m.brewster_k = Float(k);
    m.brewster_log = Float(std::log1p(k));
    m.brewster_c = Float(k / (2 * kPiD * std::log1p(k)));
    m.update_coat();
    return m;
  }
  // After the coat's roughness changed (a textured alpha).
  void update_coat() {
    if (coat) coat_albedo.prepare_roughness(coat->alpha_x);
    transmit = smooth() ? transmit_smooth : 1 - coat_albedo.average(*coat);
    // Cosine sampling of the base has weights up to 1/(1 − Ē): keep it while that is ≤ 2.
    base_sampling = BaseSampling::Cosine;
    complement_norm = 0;
    if (!(transmit < Float(0.5))) return;
    if (smooth()) {
      base_sampling = BaseSampling::Brewster;
    } else if (coat->is_isotropic()) {
      const Float loss = coat_albedo.complement_loss(coat->alpha_x);
      if (loss > 0) {
        base_sampling = BaseSampling::Complement;
        complement_norm = 1 / (kPi * loss);
      }
    }
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
  // Density per solid angle of the base's sampling for cos θi = mu (> 0) and the coat's
  // reflectance ei there.
  Float base_pdf(Float mu, Float ei) const {
    switch (base_sampling) {
      case BaseSampling::Cosine: return mu * kInvPi;
      case BaseSampling::Brewster: return Float(0.5) * (mu * kInvPi + brewster_c / (1 + brewster_k * mu));
      case BaseSampling::Complement: return std::max(Float(0), 1 - ei) * mu * complement_norm;
    }
    return 0;
  }
  // A base direction (upper side).
  Vec3 sample_base(Float u1, Float u2) const {
    Float mu = 1;  // every case sets it; the initialiser quiets -Wmaybe-uninitialized
    switch (base_sampling) {
      case BaseSampling::Cosine: return square_to_cosine_hemisphere(u1, u2);
      case BaseSampling::Brewster:
        if (u1 < Float(0.5)) return square_to_cosine_hemisphere(2 * u1, u2);
        // Inverse of the CDF ln(1 + k μ)/ln(1 + k) of the density ∝ 1/(1 + k μ) on [0, 1].
        mu = std::min(Float(1), std::expm1((2 * u1 - 1) * brewster_log) / brewster_k);
        break;
      case BaseSampling::Complement: mu = coat_albedo.sample_complement(coat->alpha_x, u1); break;
    }
    const Float s = std::sqrt(std::max(Float(0), (1 - mu) * (1 + mu)));
    const Float ph = 2 * kPi * u2;
    return {s * std::cos(ph), s * std::sin(ph), mu};
  }
};

template <typename C>
struct PlasticBxDFT : PlasticCoat {
  using color_type = C;
  static constexpr std::string_view kName = "plastic";
  using U = Unpolarized<C>;  // the colour of the parameters
  U reflectance{0.5f};

  static PlasticBxDFT make(const U& reflectance, Float eta, std::optional<MicrofacetDistribution> coat) {
    PlasticBxDFT m;
    static_cast<PlasticCoat&>(m) = PlasticCoat::make(eta, coat);
    m.reflectance = reflectance;
    return m;
  }
  // The same coat over another base.
  static PlasticBxDFT make(const PlasticCoat& coat, const U& reflectance) {
    PlasticBxDFT m;
    static_cast<PlasticCoat&>(m) = coat;
    m.reflectance = reflectance;
    return m;
  }

  U base(Float eo, Float ei) const {
    const Float t = (1 - ei) * (1 - eo);
    // ρ / (η² (1 − ρ F_dr)) = ρ / ((1 − ρ) η² + ρ (1 − Ē)).
    return map(reflectance, [&](Float r) { return r / ((1 - r) * eta * eta + r * transmit); }) * (t * kInvPi);
  }
  // Probability of sampling the coat's lobe rather than the base, by expected energy; for
  // the rough coat at least (F(cos θo / 2) + F(0°)/2)/4, which bounds the coat's weights
  // by 4 (top of the file). The smooth coat's delta weight is F/P_c ≤ 1 as it is.
  Float coat_probability(const Vec3& wo, Float eo) const {
    const Float b = (1 - eo) * reflectance.average();
    const Float p = eo + b > 0 ? eo / (eo + b) : Float(1);
    if (smooth()) return p;
    if (grazing(wo)) return 0;
    const Float floor = (fresnel_dielectric(std::abs(wo.z) / 2, eta) + f0 / 2) / 4;
    return std::max(p, floor);
  }

  BSDFEvalT<C> eval(Vec3 wo, Vec3 wi, TransportMode = TransportMode::Radiance) const {
    if (!(wo.z * wi.z > 0)) return {};
    const bool flip = wo.z < 0;
    if (flip) {
      wo.z = -wo.z;
      wi.z = -wi.z;
    }
    if (!smooth()) return eval_rough(wo, wi, flip);
    // Smooth coat: the base alone (the mirror lobe is a delta), kept small so that it
    // inlines into the callers' loops.
    const Float eo = fresnel_dielectric(wo.z, eta), ei = fresnel_dielectric(wi.z, eta);
    const Float pc = coat_probability(wo, eo);
    return {base_through_coat(base(eo, ei), wo, wi), (1 - pc) * base_pdf(wi.z, ei)};
  }
  // The base as the colour type: in polarized mode seen through the coat, which polarizes
  // the light it lets in and out by τ = (T_s − T_p)/(T_s + T_p) = (R_p − R_s)/(2 − R_s − R_p)
  // at each direction (the smooth coat's Fresnel at the macroscopic angle; for a rough coat
  // an approximation, docs/polarization.md).
  C base_through_coat(const U& value, const Vec3& wo, const Vec3& wi) const {
    return depolarized_through<C>(value, [&] {
      const auto tau = [&](const Vec3& w) {
        const FresnelTerms<Float> t = fresnel_dielectric_terms(std::abs(w.z), eta);
        const Float tt = 2 - t.rs - t.rp;
        return tt > 0 ? (t.rp - t.rs) / tt : Float(0);
      };
      return std::pair<Float, Float>{tau(wo), tau(wi)};
    });
  }
  C f(const Vec3& wo, const Vec3& wi, TransportMode mode = TransportMode::Radiance) const {
    return eval(wo, wi, mode).f;
  }
  Float pdf(const Vec3& wo, const Vec3& wi, TransportMode mode = TransportMode::Radiance) const {
    return eval(wo, wi, mode).pdf;
  }

  std::optional<BSDFSampleT<C>> sample(Vec3 wo, Float u_lobe, Float u1, Float u2,
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
        const Vec3 wi_mirror{-wo.x, -wo.y, flip ? -wo.z : wo.z};
        const C w = fresnel_factor<C>(
            F / pc, [&] { return broadcast<U>(dielectric_reflection_mueller(wo.z, eta)); },
            Vec3{wo.x, wo.y, flip ? -wo.z : wo.z}, wi_mirror);
        return BSDFSampleT<C>{wi_mirror, w, pc, true, Lobe::Reflection, 1};
      }
      wi = reflect(wo, coat->sample_visible(wo, u1, u2));
      if (grazing(wi)) return std::nullopt;  // the coat lobe is 0 there
    } else {
      wi = sample_base(u1, u2);
    }
    if (!(wi.z > 0)) return std::nullopt;
    const BSDFEvalT<C> e = eval(wo, wi, mode);
    if (!(e.pdf > 0)) return std::nullopt;
    const C weight = e.f * (wi.z / e.pdf);
    if (flip) wi.z = -wi.z;
    return BSDFSampleT<C>{wi, weight, e.pdf, false, Lobe::Reflection, 1};
  }

  // The rough coat for wo.z, wi.z > 0: base coupled through E_coat, plus the coat's lobe.
  // flip: the pair was mirrored from below (for the polarization frames).
  [[gnu::noinline]] BSDFEvalT<C> eval_rough(const Vec3& wo, const Vec3& wi, bool flip) const {
    const Float eo = coat_albedo.E(*coat, wo), ei = coat_albedo.E(*coat, wi);
    C f = base_through_coat(base(eo, ei), wo, wi);
    const Float pc = coat_probability(wo, eo);
    Float pdf = (1 - pc) * base_pdf(wi.z, ei);
    if (!grazing(wo) && !grazing(wi)) {
      const Vec3 h = wo + wi;
      const Float h2 = length_squared(h);
      const Float D = coat->D_unnormalized(h, h2);
      const Float to = coat->smith_t(wo), ti = coat->smith_t(wi);
      // F at wo·wm = |wo + wi|/2 (symmetric in the pair); with T = smith_t,
      // G2 / (4 cos θo cos θi) = 1 / (2 (cos θi T(wo) + cos θo T(wi))): no product of
      // cosines that could underflow, no Λ that could overflow.
      const Float cos_h = std::min(std::sqrt(h2) / 2, Float(1));
      const Float F = fresnel_dielectric(cos_h, eta);
      const Float s = flip ? -1 : 1;
      f += fresnel_factor<C>(
          D * F / (2 * (wi.z * to + wo.z * ti)), [&] { return broadcast<U>(dielectric_reflection_mueller(cos_h, eta)); },
          Vec3{wo.x, wo.y, s * wo.z}, Vec3{wi.x, wi.y, s * wi.z});
      // Visible-normal density times dωm/dωi: D / (4 cos θo (1 + Λo)) = D / (2 (T(wo) + cos θo)).
      pdf += pc * D / (2 * (to + wo.z));
    }
    return {f, pdf};
  }

  // Closed form for the smooth coat: F(θo) + (1 − F(θo)) ρ (1 − F_dr) / (1 − ρ F_dr).
  // Unpolarized only: a Mueller matrix's albedo is its M00, the unpolarized model's. A
  // member template, so that the library's explicit instances for Mueller matrices
  // (polarization/instances.h) leave it out (clang 14 ignores a plain member's requires).
  template <typename U = C>
    requires(!kPolarized<U>)
  std::optional<DirectionalAlbedoT<C>> albedo(const Vec3& wo, TransportMode = TransportMode::Radiance) const {
    if (!smooth()) return std::nullopt;
    if (wo.z == 0) return DirectionalAlbedoT<C>{};
    const Float F = fresnel_dielectric(std::abs(wo.z), eta);
    const C b = map(reflectance, [&](Float r) { return r * transmit / ((1 - r) * eta * eta + r * transmit); });
    return DirectionalAlbedoT<C>{C(F) + b * (1 - F), C{}};
  }
};

using PlasticBxDF = PlasticBxDFT<Color>;

}  // namespace gonio
