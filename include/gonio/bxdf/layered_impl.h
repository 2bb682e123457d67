#pragma once
// The methods of LayeredBxDFT (layered.h), included by bxdf.h once BxDFT is complete.
// Formulas: the walk of Guo, Hašan & Zhao 2018 (§4: position-free vertices, the depth z
// only; §5: next-event estimation through the exit interface) in the structure of
// pbrt-v4's LayeredBxDF::f (PBR 4th ed., §14.3.2); transmittance e^{−τ/|cos θ|}
// (Beer–Lambert, σt = 1); Henyey–Greenstein phase (subsurface/henyey_greenstein.h);
// power heuristic (Veach 1997, eq. 9.13, β = 2).

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdint>

#include "gonio/bxdf/dielectric.h"
#include "gonio/bxdf/layered.h"
#include "gonio/bxdf/thin_film.h"
#include "gonio/bxdf/thindielectric.h"
#include "gonio/math/warp.h"
#include "gonio/rng.h"
#include "gonio/subsurface/henyey_greenstein.h"

namespace gonio {
namespace layered_detail {

// splitmix64's finaliser (Steele, Lea & Flood 2014): a bijective mix of 64 bits.
inline std::uint64_t mix64(std::uint64_t x) {
  x ^= x >> 30;
  x *= 0xbf58476d1ce4e5b9ULL;
  x ^= x >> 27;
  x *= 0x94d049bb133111ebULL;
  return x ^ (x >> 31);
}
// The bit pattern of a direction (−0 counted as +0: the same direction).
inline std::uint64_t direction_hash(const Vec3& w) {
  const auto b = [](Float v) { return std::uint64_t(std::bit_cast<std::uint32_t>(v + Float(0))); };
  return mix64(mix64(mix64(b(w.x) + 0x9e3779b97f4a7c15ULL) ^ b(w.y)) ^ b(w.z));
}
// A seed for the UNORDERED pair {a, b}: the same for (a, b) and (b, a).
inline std::uint64_t pair_seed(const Vec3& a, const Vec3& b) {
  const std::uint64_t ha = direction_hash(a), hb = direction_hash(b);
  return mix64(std::min(ha, hb) ^ mix64(std::max(ha, hb) + 0x632be59bd9b4e019ULL));
}
// Transmittance of a straight flight through optical depth dz along a direction with
// z component wz (Beer–Lambert, σt = 1): e^{−dz/|wz|}; 1 without a medium.
inline Float transmittance(Float dz, Float wz) {
  if (dz == 0) return 1;
  return std::exp(-std::abs(dz) / std::abs(wz));  // wz = 0: e^{−∞} = 0
}
// Power heuristic with β = 2 (Veach 1997, eq. 9.13) for densities a (the strategy used)
// and b (the other).
inline Float power_heuristic(Float a, Float b) {
  const Float a2 = a * a, b2 = b * b;
  if (!(a2 + b2 > 0)) return 0;
  if (!std::isfinite(a2 + b2)) return a >= b ? Float(1) : Float(0);
  return a2 / (a2 + b2);
}
// The direction inside a flat interface of relative index eta that refracts to w
// (both pointing up, away from the interface; Snell: sin θ_in = sin θ_out / η); false
// beyond the critical angle (η < 1).
// cos²θ_in = 1 − sin²θ/η² = (cos²θ + η² − 1)/η² is taken from w.z: 1 − x² − y² loses
// every digit at grazing (at cos θ = 2e-4 a quarter turn of w changed the density of a
// sheet's mixture by 9 %, gonio check's isotropy), and η = 1 is then exactly the identity.
inline bool refract_in(const Vec3& w, Float eta, Vec3& in) {
  const Float inv = 1 / eta;
  const Float c2 = (w.z * w.z + (eta * eta - 1)) * (inv * inv);
  if (!(c2 > 0)) return false;
  in = {w.x * inv, w.y * inv, std::sqrt(c2)};
  return true;
}
inline bool refract_out(const Vec3& v, Float eta, Vec3& out) { return refract_in(v, 1 / eta, out); }

// For an isotropic stack, f must not change when both directions turn about N (the
// validator's `isotropy`), yet each walk's samplers draw azimuths in the local frame. So
// the walk runs in a canonical frame, turned so that `ref` (its first direction, or the
// other one at normal incidence) has azimuth 0, and is seeded by the pair's invariants
// cos θo, cos θi and the dot product of their tangential parts, quantised to 2⁻¹²: a turn
// moves them by rounding only (~1e-7), which then changes no seed but in ~0.1 % of pairs.
// The products and sums are written so that a quarter turn (x, y) → (−y, x) reproduces
// every bit (the same terms, added in the other order).
struct Turn {
  Float c = 1, s = 0;
  Vec3 operator()(const Vec3& w) const { return {c * w.x + s * w.y, c * w.y - s * w.x, w.z}; }
};
inline Turn canonical_turn(const Vec3& ref, const Vec3& other) {
  const Vec3& r = ref.x != 0 || ref.y != 0 ? ref : other;
  const Float len = std::sqrt(r.x * r.x + r.y * r.y);
  if (!(len > 0)) return {};
  return {r.x / len, r.y / len};
}
inline std::uint64_t quantised(Float v) { return std::uint64_t(std::int64_t(std::lround(double(v) * 4096)) + (1 << 20)); }
inline std::uint64_t isotropic_pair_seed(const Vec3& a, const Vec3& b) {
  const std::uint64_t za = quantised(a.z), zb = quantised(b.z), d = quantised(a.x * b.x + a.y * b.y);
  return mix64(mix64(std::min(za, zb) ^ 0x9e3779b97f4a7c15ULL) ^ mix64(std::max(za, zb)) ^ (d << 40));
}

}  // namespace layered_detail

template <typename C>
BxDFFlags LayeredBxDFT<C>::flags() const {
  const BxDFFlags b = bottom->flags();
  BxDFFlags f = top.specular() ? BxDFFlags::SpecularReflection : BxDFFlags::GlossyReflection;
  if (top.specular() && has(b, BxDFFlags::Glossy)) f = f | BxDFFlags::GlossyReflection;
  if (has(b, BxDFFlags::Diffuse) || scatters()) f = f | BxDFFlags::DiffuseReflection;
  return f;
}

template <typename C>
bool LayeredBxDFT<C>::is_isotropic() const {
  return top.is_isotropic() && bottom->is_isotropic();
}

template <typename C>
C LayeredBxDFT<C>::smooth_reflectance(const Vec3& w) const {
  using U = Unpolarized<C>;
  const Float c = std::min(std::abs(w.z), Float(1));
  if (thin_top) {
    // The sheet (thindielectric.h): the same from both sides; with a film, that one
    // coherent film between two half-spaces of the outside medium.
    if (top.film.active()) return C(top.film.reflectance(c, U(1), U(0)));
    return C(thin_sheet_terms(c, top.eta).r());
  }
  if (top.film.active()) {
    // The film on the outside face, read at the outside angle (R = 1 beyond the critical one).
    const Float c1 = film_read_cos(c, top.eta, w.z < 0);
    return c1 < 0 ? C(1) : C(top.film.reflectance(c1, U(top.eta), U(0)));
  }
  return C(fresnel_dielectric(w.z, top.eta));
}

template <typename C>
std::optional<typename LayeredBxDFT<C>::Crossing> LayeredBxDFT<C>::cross_smooth_top(const Vec3& w,
                                                                                   TransportMode mode) const {
  if (w.z == 0) return std::nullopt;
  if (thin_top) {
    const C t = C(1) - smooth_reflectance(w);
    if (t.is_black()) return std::nullopt;
    return Crossing{-w, t};
  }
  const bool inside = w.z < 0;
  const Float inv = 1 / top.eta;
  const Float e = inside ? inv : top.eta;  // n(far side) / n(w's side)
  const Float inv_e = inside ? top.eta : inv;
  if (!(dielectric_cos2_t(w.z * w.z, inv_e) > 0)) return std::nullopt;  // total internal reflection
  const C t = (C(1) - smooth_reflectance(w)) * transmission_scale(e, mode);
  if (t.is_black()) return std::nullopt;
  return Crossing{DielectricBxDFT<C>::scattered(w, inv_e, false), t};
}

template <typename C>
C LayeredBxDFT<C>::walk(const Vec3& wo, const Vec3& wi, std::uint64_t seed) const {
  using namespace layered_detail;
  constexpr auto kRad = TransportMode::Radiance, kImp = TransportMode::Importance;
  Pcg32 rng(seed);
  const auto r = [&] { return std::min(rng.next_float(), kOneMinusEpsilon); };
  const bool rough = !top.specular();
  const bool base_glossy = has(bottom->flags(), BxDFFlags::Diffuse | BxDFFlags::Glossy);
  const bool medium = scatters();
  C f{};
  // The top's own reflection (a rough top; a smooth one's is the delta lobe of sample()).
  if (rough) f = top.f(wo, wi, kRad) * Float(samples);
  // A transmission through the top from w (outside): a smooth top's is taken always and
  // weighted by its probability 1 − F, rather than drawn against its reflection (pbrt-v4
  // samples the interfaces' transmission alone the same way); a rough top's is drawn, and
  // a reflection drawn instead ends the walk.
  const auto transmit = [&](const Vec3& w, TransportMode mode) -> std::optional<BSDFSampleT<C>> {
    if (rough) {
      auto t = top.sample(w, r(), r(), r(), mode);
      if (!t || t->lobe != Lobe::Transmission) return std::nullopt;
      return t;
    }
    const auto c = cross_smooth_top(w, mode);
    if (!c) return std::nullopt;  // total internal reflection
    return BSDFSampleT<C>{c->w, c->weight, 1, true, Lobe::Transmission, geometric_eta()};
  };
  for (int s = 0; s < samples; ++s) {
    // Enter through the top from wo; leave towards wi through a transmission drawn from wi
    // in the adjoint mode (f_imp(wi, d) = f_rad(d, wi)), reused at every vertex.
    const auto wos = transmit(wo, kRad);
    if (!wos || wos->wi.z == 0 || wos->weight.is_black()) continue;
    const auto wis = transmit(wi, kImp);
    if (!wis || wis->wi.z == 0 || wis->weight.is_black()) continue;
    const C wis_f_over_pdf = wis->weight * (1 / std::abs(wis->wi.z));
    const Vec3 w_exit = -wis->wi;  // direction of travel (up) of the light that leaves towards wi
    C beta = wos->weight;
    // Russian roulette compares the throughput with the one the walk entered with: the
    // entry's 1 − F(wo) (0.002 at 89.9°) would otherwise trigger it at once and make each
    // survivor carry 1/(1 − F) times a typical path (weights of 178 at 89.9°, gonio check).
    const Float beta_entry = beta.max_component();
    Float z = thickness;  // the top is at z = thickness, the bottom at 0
    Vec3 w = wos->wi;     // direction of travel
    for (int depth = 0; depth < max_depth; ++depth) {
      // Russian roulette (pbrt-v4's rule, relative to the entry): from depth 4, a path
      // carrying less than a quarter survives with probability equal to its throughput.
      if (depth > 3) {
        const Float m = beta.max_component() / beta_entry;
        if (m < Float(0.25)) {
          const Float q = std::max(Float(0), 1 - m);
          if (r() < q) break;
          beta *= 1 / (1 - q);
        }
      }
      if (medium) {
        // Free flight in depth: dz ~ (1/|w.z|) e^{−dz/|w.z|} (σt = 1).
        const Float dz = -std::log1p(-r()) * std::abs(w.z);
        const Float zp = w.z > 0 ? z + dz : z - dz;
        if (zp == z) continue;
        if (zp > 0 && zp < thickness) {
          // A scattering vertex: connect to wi (next-event estimation through the top).
          const Float ph = hg_phase(dot(w, w_exit), g);
          const Float wt = rough ? power_heuristic(wis->pdf, ph) : Float(1);
          f += beta * albedo * wis_f_over_pdf * (ph * wt * transmittance(thickness - zp, w_exit.z));
          // Continue by sampling the phase function (weight p/pdf = 1).
          const Vec3 wn = hg_sample(w, g, r(), r());
          const Float pp = hg_phase(dot(w, wn), g);
          if (!(pp > 0) || wn.z == 0) break;
          beta *= albedo;
          w = wn;
          z = zp;
          // The same connection reached by the phase sample, through a rough top.
          if (rough && w.z > 0) {
            const C fe = top.f(-w, wi, kRad);
            if (!fe.is_black()) {
              const Float we = power_heuristic(pp, top.pdf(wi, -w, kImp));
              f += beta * fe * (we * transmittance(thickness - zp, w.z));
            }
          }
          continue;
        }
      } else {
        beta *= transmittance(thickness, w.z);
      }
      // The flight reached the interface it was heading for (by the direction of travel:
      // with thickness 0 both lie at the same depth).
      const bool at_top = w.z > 0;
      z = at_top ? thickness : Float(0);
      if (at_top) {
        // At the top from inside: reflect back down; what the top transmits has left
        // (its contribution towards wi is the connections above and below). A smooth top
        // reflects by its Fresnel factor (no draw); a rough one's reflection is drawn.
        if (rough) {
          const auto bs = top.sample(-w, r(), r(), r(), kRad);
          if (!bs || bs->lobe != Lobe::Reflection || bs->wi.z == 0) break;
          beta *= bs->weight;
          w = bs->wi;
        } else {
          beta *= smooth_reflectance(-w);
          w = {w.x, w.y, -w.z};
        }
      } else {
        // At the bottom: connect to wi through the top, then continue by the bottom's sampling.
        if (base_glossy) {
          const BSDFEvalT<C> be = bottom->eval(-w, w_exit, kRad);
          if (!be.f.is_black()) {
            const Float wt = rough ? power_heuristic(wis->pdf, be.pdf) : Float(1);
            f += beta * be.f * wis_f_over_pdf * (std::abs(w_exit.z) * wt * transmittance(thickness, w_exit.z));
          }
        }
        const auto bs = bottom->sample(-w, r(), r(), r(), kRad);
        if (!bs || !(bs->wi.z > 0) || bs->weight.is_black()) break;
        beta *= bs->weight;
        w = bs->wi;
        if (rough) {
          const C fe = top.f(-w, wi, kRad);
          if (!fe.is_black()) {
            const Float we = bs->delta ? Float(1) : power_heuristic(bs->pdf, top.pdf(wi, -w, kImp));
            f += beta * fe * (we * transmittance(thickness, w.z));
          }
        }
      }
      if (beta.is_black()) break;
    }
  }
  return f * (1 / Float(samples));
}

template <typename C>
C LayeredBxDFT<C>::specular_chain(const Vec3& wo, std::uint64_t seed) const {
  using namespace layered_detail;
  constexpr auto kRad = TransportMode::Radiance;
  C est = smooth_reflectance(wo);
  if (!has(bottom->flags(), BxDFFlags::Specular)) return est;
  // In and out through the top, each weighted by its share: (1 − F)² (the radiance
  // scalings cancel).
  const auto in = cross_smooth_top(wo, kRad);
  if (!in) return est;
  Vec3 w = in->w;  // travelling down
  const Vec3 up{w.x, w.y, -w.z};
  const C fi = smooth_reflectance(-up);  // the top from inside (= F: Snell's pair)
  const auto out = cross_smooth_top(-up, kRad);
  if (!out) return est;
  const C t0 = in->weight * out->weight;
  // A bottom that is one delta lobe with a closed-form reflectance R_b (mirror, conductor)
  // sends every bounce back along the same two directions: the chain is the geometric
  // series F + (1 − F)² T R_b Σ (F T R_b)^k, T = e^{−2τ/μ'}, summed exactly (a walk capped
  // at max_depth would lose (1 − F) F^max_depth near grazing, where F → 1).
  if (is_delta_only(bottom->flags())) {
    if (const auto a = bottom->exact_albedo(up, kRad)) {
      const Float T = transmittance(thickness, up.z) * transmittance(thickness, up.z);
      const C ratio = a->reflectance * fi * T;
      return est + t0 * a->reflectance * T / (C(1) - ratio);
    }
  }
  // Otherwise the chain, bounce by bounce: the bottom's choice of its delta lobe is random
  // (its weight carries the probability), the rest deterministic; no Russian roulette (the
  // throughput falls by F_in per bounce), capped at max_depth.
  Pcg32 rng(seed);
  const auto r = [&] { return std::min(rng.next_float(), kOneMinusEpsilon); };
  C t = in->weight;
  for (int depth = 0; depth < max_depth; ++depth) {
    t *= transmittance(thickness, w.z);  // unscattered: what scatters belongs to f
    const auto bs = bottom->sample(-w, r(), r(), r(), kRad);
    if (!bs || !bs->delta || !(bs->wi.z > 0)) break;
    t *= bs->weight;
    w = bs->wi;  // travelling up
    t *= transmittance(thickness, w.z);
    est += t * out->weight;
    t *= fi;
    if (t.is_black()) break;
    w = {w.x, w.y, -w.z};
  }
  return est;
}

template <typename C>
typename LayeredBxDFT<C>::Mixture LayeredBxDFT<C>::mixture(const Vec3& wo) const {
  Mixture p;
  const bool rough = !top.specular();
  const bool base_glossy = has(bottom->flags(), BxDFFlags::Diffuse | BxDFFlags::Glossy);
  Float rest = 1;
  if (!rough) {
    const bool continuous = base_glossy || scatters();
    // A coloured F (a film): halfway between its average and its least channel, so that
    // neither lobe's weight exceeds twice a channel's share over the average (the RGB
    // film table's 0.99983 against 1 at grazing made the continuous lobes' weights 10.6
    // when chosen by the average alone, the adversarial sweep).
    const C Fc = smooth_reflectance(wo);
    const Float F = (Fc.average() + Fc.min_component()) / 2;
    // The delta lobe: F alone over a bottom without one (weight 1), else at least even
    // odds (weight ≤ 2).
    p.delta = !continuous ? Float(1) : has(bottom->flags(), BxDFFlags::Specular) ? std::max(F, Float(0.5)) : F;
    rest = 1 - p.delta;
  } else {
    p.lobe = 0.3f;
    p.wide = 0.2f;
    rest = 0.5f;
  }
  // The rest in equal shares among the bottom seen through the top, the medium's lobe
  // and the cosine lobe, those that apply.
  const Float share = rest / Float(1 + int(base_glossy) + int(scatters()));
  p.base = base_glossy ? share : Float(0);
  p.medium = scatters() ? share : Float(0);
  p.cosine = rest - p.base - p.medium;
  return p;
}

namespace layered_detail {
// The wider copy of the top's distribution: light crossing the top twice is spread about
// twice as far as the top's own reflection.
inline MicrofacetDistribution widened(const MicrofacetDistribution& d) {
  MicrofacetDistribution w = d;
  w.alpha_x = std::min(2 * d.alpha_x, std::max(d.alpha_x, Float(1)));
  w.alpha_y = std::min(2 * d.alpha_y, std::max(d.alpha_y, Float(1)));
  return w;
}
// The medium's lobe inside the stack: light travelling along −vo (refracted in along wo)
// scattered once by Henyey–Greenstein, and turned back up by a mirror at the bottom when
// it went down; the density of the upward direction v sums its two preimages, v and its
// mirror image.
inline Float medium_lobe_pdf(const Vec3& vo, const Vec3& v, Float g) {
  return hg_phase(-dot(vo, v), g) + hg_phase(-dot(vo, Vec3{v.x, v.y, -v.z}), g);
}
// Density of reflect(wo, visible normal) per solid angle of wi (both up): D_wo(wm) / (4 wo·wm)
// = D / (2 (T(wo) + cos θo)) with T = smith_t (Heitz & d'Eon 2014; as plastic.h).
inline Float reflection_lobe_pdf(const MicrofacetDistribution& d, const Vec3& wo, const Vec3& wi) {
  const Vec3 h = wo + wi;
  const Float h2 = length_squared(h);
  if (!(h2 > 0)) return 0;
  return d.D_unnormalized(h, h2) / (2 * (d.smith_t(wo) + wo.z));
}
}  // namespace layered_detail

template <typename C>
Float LayeredBxDFT<C>::mixture_pdf(const Mixture& p, const Vec3& wo, const Vec3& wi) const {
  using namespace layered_detail;
  Float pdf = p.cosine * wi.z * kInvPi;
  if (p.lobe > 0) pdf += p.lobe * reflection_lobe_pdf(top.distribution, wo, wi);
  if (p.wide > 0) pdf += p.wide * reflection_lobe_pdf(widened(top.distribution), wo, wi);
  if (p.base > 0 || p.medium > 0) {
    // Densities at the refracted pair, times dω_in/dω_out = cos θ_out / (η² cos θ_in).
    const Float eta = geometric_eta();
    Vec3 vo, vi;
    if (refract_in(wo, eta, vo) && refract_in(wi, eta, vi)) {
      Float inside = 0;
      if (p.base > 0) inside += p.base * bottom->pdf(vo, vi, TransportMode::Radiance);
      if (p.medium > 0) inside += p.medium * medium_lobe_pdf(vo, vi, g);
      pdf += inside * (wi.z / (eta * eta * vi.z));
    }
  }
  return std::isfinite(pdf) ? pdf : Float(0);
}

template <typename C>
BSDFEvalT<C> LayeredBxDFT<C>::eval(const Vec3& wo_in, const Vec3& wi_in, TransportMode) const {
  if (!(wo_in.z * wi_in.z > 0)) return {};  // the stack reflects only
  const Float s = wo_in.z > 0 ? 1 : -1;  // two-sided: the stack seen from below is mirrored
  const Vec3 wo{wo_in.x, wo_in.y, s * wo_in.z}, wi{wi_in.x, wi_in.y, s * wi_in.z};
  const Float pdf = mixture_pdf(mixture(wo), wo, wi);
  // The symmetric estimator: the walk from both ends with one seed, weighted by
  // w(wo, wi) = cos²θi / (cos²θo + cos²θi) and w(wi, wo) (layered.h), so f(wo, wi) =
  // f(wi, wo) exactly (the same two products, and a sum does not depend on its order).
  const Float zo2 = wo.z * wo.z, zi2 = wi.z * wi.z;
  const bool both_tiny = !(zo2 + zi2 > 0);  // squares underflowed: even weights
  const Float wa = both_tiny ? Float(0.5) : zi2 / (zo2 + zi2), wb = both_tiny ? Float(0.5) : zo2 / (zi2 + zo2);
  C a, b;
  if (is_isotropic()) {
    using namespace layered_detail;
    const std::uint64_t seed = isotropic_pair_seed(wo, wi);
    const Turn to = canonical_turn(wo, wi), ti = canonical_turn(wi, wo);
    a = walk(to(wo), to(wi), seed);
    b = walk(ti(wi), ti(wo), seed);
  } else {
    const std::uint64_t seed = layered_detail::pair_seed(wo, wi);
    a = walk(wo, wi, seed);
    b = walk(wi, wo, seed);
  }
  C f = a * wa + b * wb;
  if (!f.is_finite()) f = C{};
  return {f, pdf};
}

template <typename C>
C LayeredBxDFT<C>::f(const Vec3& wo, const Vec3& wi, TransportMode mode) const {
  return eval(wo, wi, mode).f;
}

template <typename C>
Float LayeredBxDFT<C>::pdf(const Vec3& wo, const Vec3& wi, TransportMode) const {
  if (!(wo.z * wi.z > 0)) return 0;
  const Float s = wo.z > 0 ? 1 : -1;
  const Vec3 o{wo.x, wo.y, s * wo.z}, i{wi.x, wi.y, s * wi.z};
  return mixture_pdf(mixture(o), o, i);
}

template <typename C>
std::optional<BSDFSampleT<C>> LayeredBxDFT<C>::sample(const Vec3& wo_in, Float u_lobe, Float u1, Float u2,
                                                      TransportMode mode) const {
  using namespace layered_detail;
  if (wo_in.z == 0) return std::nullopt;
  const Float s = wo_in.z > 0 ? 1 : -1;
  const Vec3 wo{wo_in.x, wo_in.y, s * wo_in.z};
  const Mixture p = mixture(wo);
  Float u = u_lobe;
  Vec3 wi;
  if (u < p.delta) {
    // The specular chain, estimated with a generator seeded by this sample.
    // (By cos θo alone when isotropic: the chain's weight does not depend on the azimuth.)
    const std::uint64_t where = is_isotropic() ? quantised(wo.z) : direction_hash(wo);
    const std::uint64_t seed = mix64(where ^ mix64(std::uint64_t(std::bit_cast<std::uint32_t>(u1)) << 32 |
                                                   std::bit_cast<std::uint32_t>(u2)));
    const C R = specular_chain(wo, seed);
    return BSDFSampleT<C>{{-wo.x, -wo.y, s * wo.z}, R * (1 / p.delta), p.delta, true, Lobe::Reflection, 1};
  }
  u -= p.delta;
  if (u < p.lobe) {
    wi = reflect(wo, top.distribution.sample_visible(wo, u1, u2));
  } else if ((u -= p.lobe) < p.wide) {
    wi = reflect(wo, widened(top.distribution).sample_visible(wo, u1, u2));
  } else if ((u -= p.wide) < p.base) {
    Vec3 vo;
    if (!refract_in(wo, geometric_eta(), vo)) return std::nullopt;
    const auto bs = bottom->sample(vo, std::min(u / p.base, kOneMinusEpsilon), u1, u2, TransportMode::Radiance);
    if (!bs || bs->delta || !(bs->wi.z > 0) || !refract_out(bs->wi, geometric_eta(), wi)) return std::nullopt;
  } else if ((u -= p.base) < p.medium) {
    Vec3 vo;
    if (!refract_in(wo, geometric_eta(), vo)) return std::nullopt;
    Vec3 v = hg_sample(-vo, g, u1, u2);
    v.z = std::abs(v.z);  // the mirror at the bottom
    if (!(v.z > 0) || !refract_out(v, geometric_eta(), wi)) return std::nullopt;
  } else {
    wi = square_to_cosine_hemisphere(u1, u2);
  }
  if (!(wi.z > 0)) return std::nullopt;
  const BSDFEvalT<C> e = eval(wo, wi, mode);
  if (!(e.pdf > 0)) return std::nullopt;
  const C weight = e.f * (wi.z / e.pdf);
  wi.z *= s;
  return BSDFSampleT<C>{wi, weight, e.pdf, false, Lobe::Reflection, 1};
}

}  // namespace gonio
