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
#include "gonio/dielectric_multiscatter.h"
#include "gonio/fresnel.h"
#include "gonio/microfacet.h"
#include "gonio/polarization/fresnel_factor.h"
#include "gonio/polarization/interface.h"

namespace gonio {

template <typename C>
struct RoughDielectricBxDFT {
  using color_type = C;
  static constexpr std::string_view kName = "roughdielectric";
  MicrofacetDistribution distribution;
  Float eta = 1.5f;  // n_inside / n_outside
  // Kulla & Conty's energy compensation (dielectric_multiscatter.h), when enabled; only
  // for a model that is not specular().
  std::optional<DielectricMultiscatterLobe> multiscatter;
  // A thin film on the outside face (thin_film.h; inactive: the bare interface). The
  // parser refuses it together with multiscatter (whose tables are of the bare interface);
  // openpbr's glass, whose film covers a share w of it, keeps the compensation for the bare
  // share only: the lobe times 1 − w (the film's share, with no lobe, never gains energy;
  // with the bare lobe at full weight a film measured 1.005 at 79°).
  ThinFilmT<Unpolarized<C>> film{};

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
  static constexpr Float kGrazing = 1e-7f;
  static bool grazing(const Vec3& w) { return std::abs(w.z) < kGrazing; }
  bool is_isotropic() const { return distribution.is_isotropic(); }

  // Each entry point runs code instantiated for its distribution type (see is_ggx).
  BSDFEvalT<C> eval(const Vec3& wo, const Vec3& wi, TransportMode mode = TransportMode::Radiance) const {
    BSDFEvalT<C> e = distribution.type == MicrofacetType::GGX
                     ? evaluate<true, static_cast<int>(MicrofacetType::GGX)>(wo, wi, mode)
                     : evaluate<true, static_cast<int>(MicrofacetType::Beckmann)>(wo, wi, mode);
    if (multiscatter) add_multiscatter(wo, wi, mode, e);
    return e;
  }
  C f(const Vec3& wo, const Vec3& wi, TransportMode mode = TransportMode::Radiance) const {
    return eval(wo, wi, mode).f;
  }
  Float pdf(const Vec3& wo, const Vec3& wi, TransportMode mode = TransportMode::Radiance) const {
    if (multiscatter) return eval(wo, wi, mode).pdf;
    return distribution.type == MicrofacetType::GGX ? evaluate<false, static_cast<int>(MicrofacetType::GGX)>(wo, wi, mode).pdf
                                                    : evaluate<false, static_cast<int>(MicrofacetType::Beckmann)>(wo, wi, mode).pdf;
  }

  std::optional<BSDFSampleT<C>> sample(const Vec3& wo, Float u_lobe, Float u1, Float u2,
                                   TransportMode mode = TransportMode::Radiance) const {
    if (specular()) return DielectricBxDFT<C>{eta, film}.sample(wo, u_lobe, u1, u2, mode);
    if (grazing(wo)) return std::nullopt;
    if (multiscatter) return sample_mixture(wo, u_lobe, u1, u2, mode);
    constexpr int kGGX = static_cast<int>(MicrofacetType::GGX), kBeckmann = static_cast<int>(MicrofacetType::Beckmann);
    if (distribution.type == MicrofacetType::GGX) {
      return wo.z > 0 ? sample_rough<kGGX, true>(wo, u_lobe, u1, u2, mode)
                      : sample_rough<kGGX, false>(wo, u_lobe, u1, u2, mode);
    }
    return wo.z > 0 ? sample_rough<kBeckmann, true>(wo, u_lobe, u1, u2, mode)
                    : sample_rough<kBeckmann, false>(wo, u_lobe, u1, u2, mode);
  }

 private:
  // Adds the compensation lobe to a single-scattering evaluation: f (radiance mode: times
  // (n_wo/n_wi)² on transmission, SPEC §1) and the mixture's density.
  void add_multiscatter(const Vec3& wo, const Vec3& wi, TransportMode mode, BSDFEvalT<C>& e) const {
    if (grazing(wo) || grazing(wi)) return;
    const bool wo_out = wo.z > 0, wi_out = wi.z > 0;
    const Float cos_o = std::abs(wo.z), cos_i = std::abs(wi.z);
    Float f = multiscatter->f_importance(wo_out, wi_out, cos_o, cos_i) * (film.active() ? 1 - film.coverage : Float(1));
    if (wo_out != wi_out && mode == TransportMode::Radiance) {
      const Float ratio = wo_out ? 1 / eta : eta;  // n_wo / n_wi
      f *= ratio * ratio;
    }
    const Float p = multiscatter->probability(wo_out, cos_o);
    e.f += C(f);
    e.pdf = (1 - p) * e.pdf + p * multiscatter->pdf(wo_out, wi_out, cos_i);
  }

  // Sampling of the mixture: the compensation lobe with its probability (a cosine-weighted
  // direction on the side chosen by its reflection/transmission split), else the
  // single-scattering sampler; the weight is f |cos θi| / pdf of the mixture.
  std::optional<BSDFSampleT<C>> sample_mixture(const Vec3& wo, Float u_lobe, Float u1, Float u2,
                                           TransportMode mode) const {
    const bool wo_out = wo.z > 0;
    const Float p = multiscatter->probability(wo_out, std::abs(wo.z));
    Vec3 wi;
    if (u_lobe < p) {
      const Float u = u_lobe / p;
      const Float reflect_share = wo_out ? multiscatter->r_out : multiscatter->r_in;
      wi = square_to_cosine_hemisphere(u1, u2);
      // Reflection stays on wo's side; transmission goes to the other.
      const bool same_side = u < reflect_share;
      if (wo_out != same_side) wi.z = -wi.z;
    } else {
      const Float u = std::min((u_lobe - p) / (1 - p), kOneMinusEpsilon);
      constexpr int kGGX = static_cast<int>(MicrofacetType::GGX), kBeckmann = static_cast<int>(MicrofacetType::Beckmann);
      const auto s = distribution.type == MicrofacetType::GGX
                         ? (wo_out ? sample_rough<kGGX, true>(wo, u, u1, u2, mode) : sample_rough<kGGX, false>(wo, u, u1, u2, mode))
                         : (wo_out ? sample_rough<kBeckmann, true>(wo, u, u1, u2, mode)
                                   : sample_rough<kBeckmann, false>(wo, u, u1, u2, mode));
      if (!s) return std::nullopt;
      wi = s->wi;
    }
    if (grazing(wi)) return std::nullopt;
    const BSDFEvalT<C> e = eval(wo, wi, mode);
    if (!(e.pdf > 0)) return std::nullopt;
    const bool transmit = (wi.z > 0) != wo_out;
    const Float crossed = transmit ? (wo_out ? eta : 1 / eta) : Float(1);
    return BSDFSampleT<C>{wi, e.f * (std::abs(wi.z) / e.pdf), e.pdf, false,
                      transmit ? Lobe::Transmission : Lobe::Reflection, crossed};
  }

  // The sampler per distribution type and side of wo (outside: wo.z > 0).
  template <int kType, bool kOutside>
  [[gnu::always_inline]] std::optional<BSDFSampleT<C>> sample_rough(const Vec3& wo, Float u_lobe, Float u1, Float u2,
                                                                TransportMode mode) const {
    constexpr bool outside = kOutside;
    // Normals visible from wo; from inside, those visible from −wo (the same
    // distribution, as D_w uses |w·wm|).
    const Vec3 wv = outside ? wo : -wo;
    const auto vn = distribution.sample_visible_terms<kType>(wv, u1, u2);
    const Float to = distribution.smith_t<kType>(wv);  // = smith_t(wo); the sampler's stretched length (CSE)
    const Float inv_eta = 1 / eta;
    const Float e = outside ? eta : inv_eta;  // n(far side) / n(wo's side)
    const Float inv_e = outside ? inv_eta : eta;
    const Float cos_o = std::abs(wo.z);
    // With wm = m/|m| and om = wo·m: |wo·wm| = |om|/|m| and, by Snell's law (lecture §5.3),
    // t = |m|² cos²θt = |m|² − (|m|² − om²)/e² (t ≤ 0: total internal reflection). The
    // directions below need only 1/|m|² and sqrt(t), not wm itself.
    const Float om = dot(wo, vn.m);
    const Float inv_m2 = 1 / vn.m2;
    const Float inv_m = std::sqrt(inv_m2);
    const Float t = vn.m2 - (vn.m2 - om * om) * (inv_e * inv_e);
    const bool tir = !(t > 0);
    const Float st = std::sqrt(std::max(t, Float(0)));
    // Fresnel (Hecht §4.6.2) of the sampled facet chooses the lobe.
    // With a film: its reflectance per channel at the facet's outside cosine, the lobe
    // chosen by the channel average (each channel weighted by its share over it).
    using U = Unpolarized<C>;
    U film_r{};
    Float F;
    if (film.active()) {
      const Float c_out = std::min(outside ? std::abs(om) * inv_m : st * inv_m, Float(1));
      film_r = tir ? U(1) : film.reflectance(c_out, U(eta), U(0));
      F = tir ? Float(1) : std::clamp(film_r.average(), Float(0), Float(1));
    } else {
      F = tir ? Float(1) : fresnel_dielectric_parts(std::min(std::abs(om) * inv_m, Float(1)), st * inv_m, e).r();
    }
    // The weight f |cos θi| / pdf is G2/G1(wo) in closed form, times (n_wo/n_wi)² for a
    // refraction in radiance mode (Heitz & d'Eon 2014; Walter et al. 2007, eqs. 20, 21):
    // D, F and the Jacobian cancel. The pdf is that of the returned pair, computed as pdf()
    // computes it (from_half) but with T(wo) known: for a narrow lobe D(wm) is steep, and F
    // near a facet's critical angle, enough that the rounding of wi alone would move a
    // closed form from the sampled normal by more than 1e-4.
    const Float to_plus = to + cos_o;
    const bool reflect_lobe = u_lobe < F;
    Vec3 wi;
    if (reflect_lobe) {
      wi = vn.m * (2 * (om * inv_m2)) - wo;  // reflect(wo, wm) = 2 (wo·wm) wm − wo (lecture §5.2)
      if (!(outside ? wi.z >= kGrazing : wi.z <= -kGrazing)) return std::nullopt;  // same side, not grazing
    } else {
      if (tir) return std::nullopt;
      // Refraction about the facet normal n = ±wm on wo's side (lecture §5.3; as refract()):
      // wi = −wo/e + (|wo·wm|/e − cos θt) n = m (om/e ∓ sqrt(t)) / |m|² − wo/e.
      wi = vn.m * ((om * inv_e - (outside ? st : -st)) * inv_m2) - wo * inv_e;
      // The two terms cancel to a unit vector only up to rounding of order 1/e: at η = 10⁻⁴
      // the sum was off unit length by a factor of 2 (issue 9's adversarial sweep).
      wi = normalize(wi);
      if (!(outside ? wi.z <= -kGrazing : wi.z >= kGrazing)) return std::nullopt;  // other side, not grazing
    }
    const Half hv = reflect_lobe ? half_vector_ab(wo, wi, true)
                    : outside    ? half_vector_ab(wo, wi, false)
                                 : half_vector_ab(wi, wo, false);  // = half_vector(wo, wi, reflect_lobe)
    if (!hv.valid) return std::nullopt;
    const Float pdf = from_half<false, kType>(wo, wi, mode, reflect_lobe, hv, to).pdf;
    if (!(pdf > 0)) return std::nullopt;
    const Float cos_i = std::abs(wi.z);
    const Float g2_den = cos_i * to + cos_o * distribution.smith_t<kType>(wi);
    const Float cos_m = std::min(std::abs(om) * inv_m, Float(1));
    if (film.active()) {
      const Float c_out = std::min(outside ? cos_m : st * inv_m, Float(1));
      const auto shape = [&] {
        if (tir) return broadcast<U>(dielectric_reflection_mueller(cos_m, e));
        return film.mueller(c_out, U(eta), U(0), reflect_lobe, reflect_lobe && !outside);
      };
      if (reflect_lobe)
        return BSDFSampleT<C>{wi, fresnel_factor<C>(film_r * (cos_i * to_plus / (g2_den * F)), shape, wo, wi), pdf,
                              false, Lobe::Reflection, 1};
      const Float scale = mode == TransportMode::Radiance ? e * e : Float(1);
      return BSDFSampleT<C>{
          wi, fresnel_factor<C>((U(1) - film_r) * (cos_i * to_plus / (g2_den * scale * (1 - F))), shape, wo, wi), pdf,
          false, Lobe::Transmission, e};
    }
    if (reflect_lobe) {
      const C w = fresnel_factor<C>(
          cos_i * to_plus / g2_den, [&] { return broadcast<Unpolarized<C>>(dielectric_reflection_mueller(cos_m, e)); },
          wo, wi);
      return BSDFSampleT<C>{wi, w, pdf, false, Lobe::Reflection, 1};
    }
    const Float scale = mode == TransportMode::Radiance ? e * e : Float(1);  // 1 / transmission_scale
    const C w = fresnel_factor<C>(
        cos_i * to_plus / (g2_den * scale),
        [&] { return broadcast<Unpolarized<C>>(dielectric_transmission_mueller(cos_m, e)); }, wo, wi);
    return BSDFSampleT<C>{wi, w, pdf, false, Lobe::Transmission, e};
  }

  // Dielectric Fresnel (fresnel.h) for |cos θ| = c (c2 = c²) on the side from which the
  // relative index to cross is e = 1/inv_e; 1 under total internal reflection.
  [[gnu::always_inline]] static Float fresnel(Float c, Float c2, Float e, Float inv_e) {
    return fresnel_dielectric_oriented(c, c2, e, inv_e);
  }

  // The reflection term with a film at the facet cosine c (from wo's side): pdf = F̄ ·
  // pdf_per_F, f = R · f_per_F per channel, R the film's reflectance (1 beyond the
  // critical angle inside), F̄ its channel average.
  template <bool kWithF>
  [[gnu::always_inline]] BSDFEvalT<C> film_reflection(const Vec3& wo, const Vec3& wi, Float c, Float pdf_per_F,
                                                      Float f_per_F) const {
    using U = Unpolarized<C>;
    const Float c1 = film_read_cos(c, eta, wo.z < 0);
    const U r = c1 < 0 ? U(1) : film.reflectance(c1, U(eta), U(0));
    const Float pdf = std::clamp(r.average(), Float(0), Float(1)) * pdf_per_F;
    if constexpr (!kWithF) return {C{}, pdf};
    const auto shape = [&] {
      if (c1 < 0) return broadcast<U>(dielectric_reflection_mueller(c, wo.z < 0 ? 1 / eta : eta));
      return film.mueller(c1, U(eta), U(0), true, wo.z < 0);
    };
    return {fresnel_factor<C>(r * f_per_F, shape, wo, wi), pdf};
  }

  // The (unnormalised) half vector of a pair and its dot products.
  struct Half {
    Vec3 h;          // ∝ wm, turned to the outside
    Float h2 = 0;    // |h|²
    Float ha = 0, hb = 0;  // a·h, b·h (a = the outside direction, or wo for reflection)
    bool valid = false;
  };
  // The half vector and every dot product are computed from the pair in a fixed order
  // (for transmission: the outside direction, then the inside one), so that f(wo, wi)
  // and f(wi, wo) use identical numbers and reciprocity holds to rounding even where
  // Fresnel is steep, at the critical angle of a microfacet.
  [[gnu::always_inline]] Half half_vector(const Vec3& wo, const Vec3& wi, bool reflection) const {
    if (reflection) return half_vector_ab(wo, wi, true);
    return wo.z > 0 ? half_vector_ab(wo, wi, false) : half_vector_ab(wi, wo, false);
  }
  // a: the outside direction (or wo, for reflection), b: the inside one (or wi). By value,
  // so that a caller's directions can stay in registers.
  [[gnu::always_inline]] Half half_vector_ab(const Vec3 a, const Vec3 b, bool reflection) const {
    // h ∝ n_a a + n_b b (Walter et al. 2007, eq. 16), turned to the outside.
    Half r;
    r.h = reflection ? a + b : a + b * eta;
    r.h2 = length_squared(r.h);
    if (r.h2 == 0) return r;
    if (r.h.z < 0) r.h = -r.h;
    r.ha = dot(a, r.h);
    r.hb = dot(b, r.h);
    // Microfacets seen from behind by either direction contribute nothing.
    r.valid = !(r.ha * a.z <= 0 || r.hb * b.z <= 0);
    return r;
  }

  // f and pdf (kWithF) or the pdf alone, from one code path. The hot helpers are forced
  // inline: called out of line, their small structs travel through memory and the
  // reloads stall on store forwarding.
  template <bool kWithF, int kType>
  [[gnu::always_inline]] BSDFEvalT<C> evaluate(const Vec3& wo, const Vec3& wi, TransportMode mode) const {
    if (specular() || grazing(wo) || grazing(wi)) return {};
    const bool reflection = (wo.z > 0) == (wi.z > 0);
    const Half hv = half_vector(wo, wi, reflection);
    if (!hv.valid) return {};
    return from_half<kWithF, kType>(wo, wi, mode, reflection, hv, distribution.smith_t<kType>(wo));
  }

  // eval given the half vector and T(wo) = smith_t(wo); sample() calls it for its pdf.
  template <bool kWithF, int kType>
  [[gnu::always_inline]] BSDFEvalT<C> from_half(const Vec3& wo, const Vec3& wi, TransportMode mode, bool reflection, const Half& hv,
                     Float to) const {
    const Float cos_o = std::abs(wo.z), cos_i = std::abs(wi.z);
    const Float to_plus = to + cos_o;
    // With T = smith_t: G2 / (|cos θo| |cos θi|) = 2 / (|cos θi| T(wo) + |cos θo| T(wi)) and
    // D_wo(wm) = G1(wo) |wo·wm| D / |cos θo| = 2 D |wo·wm| / (T(wo) + |cos θo|).
    const auto g2_over_cos = [&] { return 2 / (cos_i * to + cos_o * distribution.smith_t<kType>(wi)); };
    if (reflection) {
      // F at wo·wm = wi·wm = |wo + wi|/2 (for unit wo, wi): symmetric in the pair, and free
      // of the cancellation in wo·h = 1 + wo·wi near grazing.
      const Float c2 = std::min(hv.h2 / 4, Float(1)), c = std::sqrt(c2);
      const Float D = distribution.D_unnormalized<kType>(hv.h, hv.h2);
      if (film.active()) return film_reflection<kWithF>(wo, wi, c, D / (2 * to_plus), D * g2_over_cos() / 4);
      const Float F = wo.z < 0 ? fresnel(c, c2, 1 / eta, eta) : fresnel(c, c2, eta, 1 / eta);
      // pdf = D_wo / (4 |wo·wm|) F = F D / (2 (T(wo) + |cos θo|)) (Walter et al. 2007, eq. 14)
      const Float pdf = F * (D / (2 * to_plus));
      if constexpr (!kWithF) return {C{}, pdf};
      // f = D G2 F / (4 |cos θo| |cos θi|) (eq. 20)
      return {fresnel_factor<C>(
                  F * (D * g2_over_cos() / 4),
                  [&] { return broadcast<Unpolarized<C>>(dielectric_reflection_mueller(c, wo.z < 0 ? 1 / eta : eta)); },
                  wo, wi),
              pdf};
    }
    // Transmittance 1 − F of the pair from its two cosines with the facet normal,
    // ca = a·h > 0 outside and cb = −b·h > 0 inside, in the common scale |h| (which Fresnel
    // ignores, fresnel.h: Snell's law holds for the pair by construction of h, so no sqrt
    // is needed), in the cancellation-free form 1 − F = t_numerator / t_denominator.
    const Float ca = hv.ha, cb = -hv.hb;
    const auto fr = fresnel_dielectric_parts(ca, cb, eta);
    const Float dots = ca * cb;
    const Float D = distribution.D_unnormalized<kType>(hv.h, hv.h2);
    // With a film: 1 − R of the film-covered facet at its outside cosine (thin_film.h),
    // the channel average for the density.
    using U = Unpolarized<C>;
    const Float c_film = film.active() ? std::min(ca / std::sqrt(hv.h2), Float(1)) : Float(0);
    const U film_t = film.active() ? U(1) - film.reflectance(c_film, U(eta), U(0)) : U(1);
    // (1 − F) / |h|⁴ as one quotient (D kept apart: it can be huge for a narrow lobe)
    const Float num = film.active() ? std::max(film_t.average(), Float(0)) : fr.t_numerator();
    const Float den = (film.active() ? Float(1) : fr.t_denominator()) * (hv.h2 * hv.h2);
    // pdf = D_wo(wm) dωm/dωi (1 − F), with dωm/dωi = n_wi² |wi·wm| / S (eq. 17) and
    // S = (n_a a·wm + n_b b·wm)² = |h|² for h = n_a a + n_b b; in terms of h:
    // 2 (1 − F) (D/|h|⁴) |a·h| |b·h| n_wi² / (T(wo) + |cos θo|).
    const Float n_wi2 = wo.z > 0 ? eta * eta : Float(1);
    const Float pdf = den > 0 ? num / (den * to_plus) * D * (dots * n_wi2 * 2) : Float(0);
    if constexpr (!kWithF) return {C{}, pdf};
    // Eq. 21 in radiance mode, with wo outside (n_wo = 1, n_wi = η):
    //   f = D G2 (1 − F) |a·wm| |b·wm| / (|cos θa| |cos θb| S);
    // with wo inside it is η² times that (the generalized reciprocity of SPEC §1).
    // Importance mode differs by (n_wi/n_wo)².
    const Float base = den > 0 ? num / den * D * (dots * g2_over_cos()) : Float(0);
    const Float eta_crossed = wo.z > 0 ? eta : 1 / eta;  // n_wi / n_wo
    const Float f = base * (wo.z > 0 ? Float(1) : eta * eta) * (mode == TransportMode::Radiance ? Float(1) : eta_crossed * eta_crossed);
    // The power transmission of the facet, the same from either side (polarization/interface.h).
    const auto shape = [&] {
      if (film.active()) return film.mueller(c_film, U(eta), U(0), false, false);
      return broadcast<Unpolarized<C>>(dielectric_transmission_mueller(std::min(ca / std::sqrt(hv.h2), Float(1)), eta));
    };
    if (film.active()) {
      // f as above with the channel's own 1 − R in place of the average.
      const Float avg = num;
      const U fc = avg > 0 ? film_t * (f / avg) : U(0);
      return {fresnel_factor<C>(fc, shape, wo, wi), pdf};
    }
    return {fresnel_factor<C>(f, shape, wo, wi), pdf};
  }
};

using RoughDielectricBxDF = RoughDielectricBxDFT<Color>;

}  // namespace gonio
