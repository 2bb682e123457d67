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
#include "gonio/math/hash.h"
#include "gonio/math/warp.h"
#include "gonio/rng.h"
#include "gonio/subsurface/henyey_greenstein.h"

namespace gonio {
namespace layered_detail {

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
// A direction of travel t crossing a flat interface into a medium of relative index eta
// (n_far / n_near; Snell): the tangential part divided by eta, the side kept; false
// beyond the critical angle.
inline bool refract_travel(const Vec3& t, Float eta, Vec3& out) {
  if (!refract_in(t, eta, out)) return false;
  out.z = std::copysign(out.z, t.z);
  return true;
}

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
bool LayeredBxDFT<C>::transmits() const {
  return is_transmissive(bottom->flags());
}

template <typename C>
Float LayeredBxDFT<C>::relative_eta() const {
  return transmits() ? geometric_eta() * bottom->relative_eta() : Float(1);
}

template <typename C>
BxDFFlags LayeredBxDFT<C>::flags() const {
  const BxDFFlags b = bottom->flags();
  BxDFFlags f = top.specular() ? BxDFFlags::SpecularReflection : BxDFFlags::GlossyReflection;
  if (top.specular() && has(b, BxDFFlags::Glossy)) f = f | BxDFFlags::GlossyReflection;
  if (has(b, BxDFFlags::Diffuse) || scatters()) f = f | BxDFFlags::DiffuseReflection;
  if (transmits()) {
    // Seen from below, the bottom's own delta reflection; through both, a delta
    // transmission only where the top is smooth.
    if (has(b, BxDFFlags::Specular)) {
      f = f | BxDFFlags::SpecularReflection;
      if (top.specular()) f = f | BxDFFlags::SpecularTransmission;
    }
    if (has(b, BxDFFlags::Diffuse) || scatters()) f = f | BxDFFlags::DiffuseTransmission;
    if (!top.specular() || has(b, BxDFFlags::Glossy)) f = f | BxDFFlags::GlossyTransmission;
  }
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
bool LayeredBxDFT<C>::interface_delta(bool at_top) const {
  return at_top ? top.specular() : !has(bottom->flags(), BxDFFlags::Diffuse | BxDFFlags::Glossy);
}

template <typename C>
BSDFEvalT<C> LayeredBxDFT<C>::interface_eval(bool at_top, const Vec3& wo, const Vec3& wi, TransportMode mode) const {
  if (at_top) return top.specular() ? BSDFEvalT<C>{} : top.eval(wo, wi, mode);
  return bottom->eval(wo, wi, mode);
}

template <typename C>
Float LayeredBxDFT<C>::interface_pdf(bool at_top, const Vec3& wo, const Vec3& wi, TransportMode mode) const {
  if (at_top) return top.specular() ? Float(0) : top.pdf(wo, wi, mode);
  return bottom->pdf(wo, wi, mode);
}

template <typename C>
template <typename Rand>
std::optional<BSDFSampleT<C>> LayeredBxDFT<C>::interface_sample(bool at_top, const Vec3& w, bool reflect,
                                                                TransportMode mode, Rand& r) const {
  if (at_top && top.specular()) {
    // A smooth top (or sheet) draws nothing: its reflection weighs F, its crossing 1 − F
    // (pbrt-v4 samples the interfaces' transmission alone the same way).
    if (reflect) return BSDFSampleT<C>{{-w.x, -w.y, w.z}, smooth_reflectance(w), 1, true, Lobe::Reflection, 1};
    const auto c = cross_smooth_top(w, mode);
    if (!c || c->w.z == 0) return std::nullopt;  // total internal reflection
    return BSDFSampleT<C>{c->w, c->weight, 1, true, Lobe::Transmission, 1};
  }
  const Float u0 = r(), u1 = r(), u2 = r();
  auto s = at_top ? top.sample(w, u0, u1, u2, mode) : bottom->sample(w, u0, u1, u2, mode);
  if (!s || s->wi.z == 0 || (s->wi.z * w.z > 0) != reflect || s->weight.is_black()) return std::nullopt;
  return s;
}

template <typename C>
template <typename Rand>
C LayeredBxDFT<C>::delta_legs_to_exit(const Vec3& w, Float zp, const Vec3& w_exit, bool exit_top, Rand& r) const {
  using namespace layered_detail;
  constexpr auto kRad = TransportMode::Radiance;
  const Vec3 w_back{w_exit.x, w_exit.y, -w_exit.z};  // towards the other interface
  const Float exit_z = exit_top ? thickness : Float(0), other_z = exit_top ? Float(0) : thickness;
  C legs = C(hg_phase(dot(w, w_exit), g) * transmittance(exit_z - zp, w_exit.z));
  const auto back = interface_sample(!exit_top, -w_back, true, kRad, r);
  if (back && back->delta)
    legs += back->weight * (hg_phase(dot(w, w_back), g) * transmittance(zp - other_z, w_back.z) *
                            transmittance(thickness, w_exit.z));
  C sum = legs, t(1);
  for (int depth = 0; depth < max_depth; ++depth) {
    const auto at_exit = interface_sample(exit_top, -w_exit, true, kRad, r);
    if (!at_exit || !at_exit->delta) break;
    const auto at_other = interface_sample(!exit_top, -w_back, true, kRad, r);
    if (!at_other || !at_other->delta) break;
    const Float tr = transmittance(thickness, w_exit.z);
    t *= at_exit->weight * at_other->weight * (tr * tr);
    // Russian roulette once the round trips have lost three quarters.
    const Float m = t.max_component();
    if (!(m > 0)) break;
    if (m < Float(0.25)) {
      if (r() >= m) break;
      t *= 1 / m;
    }
    sum += legs * t;
  }
  return sum;
}

template <typename C>
C LayeredBxDFT<C>::walk(const Vec3& wo, const Vec3& wi, std::uint64_t seed) const {
  using namespace layered_detail;
  constexpr auto kRad = TransportMode::Radiance, kImp = TransportMode::Importance;
  Pcg32 rng(seed);
  const auto r = [&] { return std::min(rng.next_float(), kOneMinusEpsilon); };
  // The walk enters through the interface on wo's side and leaves through the one on
  // wi's (the top for a stack that reflects only).
  const bool enter_top = wo.z > 0, exit_top = wi.z > 0;
  const Float exit_z = exit_top ? thickness : Float(0);
  const bool exit_delta = interface_delta(exit_top), other_delta = interface_delta(!exit_top);
  const auto towards_exit = [&](const Vec3& w) { return (w.z > 0) == exit_top; };
  const bool medium = scatters();
  C f{};
  // The entry interface's own reflection (a smooth one's is a delta lobe of sample()).
  if (enter_top == exit_top && !exit_delta) f = interface_eval(exit_top, wo, wi, kRad).f * Float(samples);
  for (int s = 0; s < samples; ++s) {
    // Enter through one interface from wo; leave towards wi through a transmission drawn
    // from wi in the adjoint mode (f_imp(wi, d) = f_rad(d, wi)), reused at every vertex.
    // Either draw may pick a reflection instead (its weight carries that chance): without
    // wos the path does not start, without wis this sample makes no connection (nee),
    // but every term that needs neither still counts — dropping the walk with wis would
    // scale the exit's own terms by the chance of a transmission, a bias.
    const auto wos = interface_sample(enter_top, wo, false, kRad, r);
    const auto wis = interface_sample(exit_top, wi, false, kImp, r);
    const bool nee = wis.has_value();
    const C wis_f_over_pdf = nee ? wis->weight * (1 / std::abs(wis->wi.z)) : C{};
    const Vec3 w_exit = nee ? -wis->wi : Vec3{};  // direction of travel of the light that leaves towards wi
    if (enter_top != exit_top && nee && !other_delta) {
      // Through the stack the entry is the exit's opposite interface, and the light may
      // cross straight to the exit (the loop counts only paths that turned at least
      // once): the entry's connection to wi, as at the other interface below...
      const BSDFEvalT<C> be = interface_eval(enter_top, wo, w_exit, kRad);
      if (!be.f.is_black()) {
        const Float wt = exit_delta ? Float(1) : power_heuristic(wis->pdf, be.pdf);
        f += be.f * wis_f_over_pdf * (std::abs(w_exit.z) * wt * transmittance(thickness, w_exit.z));
      }
    }
    if (!wos) continue;
    C beta = wos->weight;
    // Russian roulette compares the throughput with the one the walk entered with: the
    // entry's 1 − F(wo) (0.002 at 89.9°) would otherwise trigger it at once and make each
    // survivor carry 1/(1 − F) times a typical path (weights of 178 at 89.9°, gonio check).
    const Float beta_entry = beta.max_component();
    Float z = enter_top ? thickness : Float(0);  // the top is at z = thickness, the bottom at 0
    Vec3 w = wos->wi;                            // direction of travel
    if (enter_top != exit_top && !exit_delta) {
      // ... and the entry's sample reaching the exit.
      const C fe = interface_eval(exit_top, -w, wi, kRad).f;
      if (!fe.is_black()) {
        const Float we = wos->delta ? Float(1) : power_heuristic(wos->pdf, interface_pdf(exit_top, wi, -w, kImp));
        f += beta * fe * (we * transmittance(thickness, w.z));
      }
    }
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
          // A scattering vertex: connect to wi (next-event estimation through the exit).
          if (nee && !(exit_delta && other_delta)) {
            const Float ph = hg_phase(dot(w, w_exit), g);
            const Float wt = exit_delta ? Float(1) : power_heuristic(wis->pdf, ph);
            f += beta * albedo * wis_f_over_pdf * (ph * wt * transmittance(exit_z - zp, w_exit.z));
          } else if (nee) {
            // Both interfaces delta: nothing after this vertex can connect, so the light
            // that reaches wi unscattered is summed here, the direct leg and the leg by
            // the other interface, then the bounces between the two (each reflectance
            // drawn, so the series is unbiased).
            f += beta * albedo * wis_f_over_pdf * delta_legs_to_exit(w, zp, w_exit, exit_top, r);
          }
          // Continue by sampling the phase function (weight p/pdf = 1).
          const Vec3 wn = hg_sample(w, g, r(), r());
          const Float pp = hg_phase(dot(w, wn), g);
          if (!(pp > 0) || wn.z == 0) break;
          beta *= albedo;
          w = wn;
          z = zp;
          // The same connection reached by the phase sample, through a non-delta exit.
          if (!exit_delta && towards_exit(w)) {
            const C fe = interface_eval(exit_top, -w, wi, kRad).f;
            if (!fe.is_black()) {
              const Float we = power_heuristic(pp, interface_pdf(exit_top, wi, -w, kImp));
              f += beta * fe * (we * transmittance(exit_z - zp, w.z));
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
      if (at_top == exit_top) {
        // At the exit from inside: reflect back; what it transmits has left (its
        // contribution towards wi is the connections made elsewhere).
        const auto bs = interface_sample(exit_top, -w, true, kRad, r);
        if (!bs) break;
        beta *= bs->weight;
        w = bs->wi;
      } else {
        // At the other interface: connect to wi through the exit, then continue by its sampling.
        if (nee && !other_delta) {
          const BSDFEvalT<C> be = interface_eval(!exit_top, -w, w_exit, kRad);
          if (!be.f.is_black()) {
            const Float wt = exit_delta ? Float(1) : power_heuristic(wis->pdf, be.pdf);
            f += beta * be.f * wis_f_over_pdf * (std::abs(w_exit.z) * wt * transmittance(thickness, w_exit.z));
          }
        }
        const auto bs = interface_sample(!exit_top, -w, true, kRad, r);
        if (!bs) break;
        beta *= bs->weight;
        w = bs->wi;
        if (!exit_delta) {
          const C fe = interface_eval(exit_top, -w, wi, kRad).f;
          if (!fe.is_black()) {
            const Float we = bs->delta ? Float(1) : power_heuristic(bs->pdf, interface_pdf(exit_top, wi, -w, kImp));
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
typename LayeredBxDFT<C>::Chain LayeredBxDFT<C>::transmitting_chain(const Vec3& wo, TransportMode mode,
                                                                  std::uint64_t seed) const {
  using namespace layered_detail;
  // One path of delta events from wo, each interface's choice drawn (a smooth top's
  // reflection and crossing are both followed: the crossing ends the path's share there,
  // the reflection carries on). Light leaving on wo's side adds to the reflection, on the
  // other to the transmission; every exit of a transmitting chain is along one direction.
  Chain c;
  Pcg32 rng(seed);
  const auto r = [&] { return std::min(rng.next_float(), kOneMinusEpsilon); };
  const bool from_top = wo.z > 0;
  const auto leave = [&](bool through_top, const C& t, const Vec3& w) {
    if (through_top == from_top) {
      c.reflection += t;
    } else {
      c.transmission += t;
      c.wt = w;
      c.transmitted = true;
    }
  };
  C t;
  Vec3 w;  // direction of travel inside
  if (from_top) {
    if (!top.specular()) return c;
    c.reflection = smooth_reflectance(wo);
    const auto in = cross_smooth_top(wo, mode);
    if (!in) return c;
    t = in->weight;
    w = in->w;
  } else {
    const Float u0 = r(), u1 = r(), u2 = r();
    const auto b = bottom->sample(wo, u0, u1, u2, mode);
    if (!b || !b->delta || b->wi.z == 0 || b->weight.is_black()) return c;
    if (b->wi.z < 0) {  // the bottom's own reflection, seen from below
      c.reflection = b->weight;
      return c;
    }
    t = b->weight;
    w = b->wi;
  }
  for (int depth = 0; depth < max_depth; ++depth) {
    t *= transmittance(thickness, w.z);  // unscattered: what scatters belongs to f
    if (w.z > 0) {
      // At the top from inside: out with 1 − F (a rough top has no delta crossing), back with F.
      if (!top.specular()) break;
      if (const auto out = cross_smooth_top(-w, mode)) leave(true, t * out->weight, out->w);
      t *= smooth_reflectance(-w);
      w = {w.x, w.y, -w.z};
    } else {
      const Float u0 = r(), u1 = r(), u2 = r();
      const auto b = bottom->sample(-w, u0, u1, u2, mode);
      if (!b || !b->delta || b->wi.z == 0) break;
      if (b->wi.z < 0) {  // out through the bottom
        leave(false, t * b->weight, b->wi);
        break;
      }
      t *= b->weight;
      w = b->wi;
    }
    if (t.is_black()) break;
  }
  return c;
}

template <typename C>
typename LayeredBxDFT<C>::Mixture LayeredBxDFT<C>::mixture(const Vec3& wo) const {
  Mixture p;
  const bool rough = !top.specular();
  const bool base_glossy = has(bottom->flags(), BxDFFlags::Diffuse | BxDFFlags::Glossy);
  const bool through = transmits(), bottom_delta = has(bottom->flags(), BxDFFlags::Specular);
  Float rest = 1;
  if (through && wo.z < 0) {
    // Seen from below: the delta chain (even odds for its reflection and, through a
    // smooth top, its transmission), the bottom's own sampling, and a cosine lobe on each
    // side.
    if (bottom_delta) {
      const Float d = base_glossy || scatters() || rough ? Float(0.5) : Float(1);
      p.delta = rough ? d : d / 2;
      p.delta_t = d - p.delta;
      rest = 1 - d;
      if (rough) {  // through the delta bottom, then the rough top's own transmission
        p.lobe_t = rest / 2;
        rest -= p.lobe_t;
      }
    }
    p.base = base_glossy ? rest / 2 : Float(0);
    p.cosine = (rest - p.base) / 2;
    p.cosine_far = rest - p.base - p.cosine;
    return p;
  }
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
    p.delta = !continuous ? Float(1) : bottom_delta ? std::max(F, Float(0.5)) : F;
    rest = 1 - p.delta;
    if (through && bottom_delta) {
      // Split between the chain's reflection and its transmission (about F and 1 − F).
      p.delta_t = p.delta * (Float(0.9) - Float(0.8) * F);
      p.delta -= p.delta_t;
    }
  } else if (through && bottom_delta) {
    // The top's transmission lobe reaches the far side through the bottom's refraction.
    p.lobe = 0.2f;
    p.wide = 0.1f;
    p.lobe_t = 0.3f;
    rest = 0.4f;
  } else {
    p.lobe = 0.3f;
    p.wide = 0.2f;
    rest = 0.5f;
  }
  // The rest in equal shares among the bottom seen through the top, the medium's lobe
  // and the cosine lobes (on the far side too when the stack transmits), those that apply.
  const Float share = rest / Float(1 + int(base_glossy) + int(scatters()) + int(through));
  p.base = base_glossy ? share : Float(0);
  p.medium = scatters() ? share : Float(0);
  p.cosine_far = through ? share : Float(0);
  p.cosine = rest - p.base - p.medium - p.cosine_far;
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
  const bool near = wo.z * wi.z > 0;
  Float pdf = (near ? p.cosine : p.cosine_far) * std::abs(wi.z) * kInvPi;
  const Float eta = geometric_eta();
  if (wo.z > 0 && near) {
    if (p.lobe > 0) pdf += p.lobe * reflection_lobe_pdf(top.distribution, wo, wi);
    if (p.wide > 0) pdf += p.wide * reflection_lobe_pdf(widened(top.distribution), wo, wi);
    if (p.base > 0 || p.medium > 0) {
      // Densities at the refracted pair, times dω_in/dω_out = cos θ_out / (η² cos θ_in).
      Vec3 vo, vi;
      if (refract_in(wo, eta, vo) && refract_in(wi, eta, vi)) {
        Float inside = 0;
        if (p.base > 0) inside += p.base * bottom->pdf(vo, vi, TransportMode::Radiance);
        if (p.medium > 0) inside += p.medium * medium_lobe_pdf(vo, vi, g);
        pdf += inside * (wi.z / (eta * eta * vi.z));
      }
    }
  } else if (wo.z > 0) {
    // Through the top by its macroscopic refraction, then through the bottom as it samples.
    Vec3 vo;
    if (p.base > 0 && refract_in(wo, eta, vo)) pdf += p.base * bottom->pdf(vo, wi, TransportMode::Radiance);
    // The top's transmission to d, then Snell at the bottom: dω_d/dω_wi = η_b² |cos θi| / |cos θ_d|.
    const Float eb = bottom->relative_eta();
    Vec3 d;
    if (p.lobe_t > 0 && refract_travel(wi, 1 / eb, d))
      pdf += p.lobe_t * top.pdf(wo, d, TransportMode::Radiance) * (eb * eb * std::abs(wi.z) / std::abs(d.z));
  } else {
    // From below: the bottom's own sampling, refracted out through the top when it crosses.
    Vec3 v;
    if (p.base > 0) {
      if (near)
        pdf += p.base * bottom->pdf(wo, wi, TransportMode::Radiance);
      else if (refract_in(wi, eta, v))
        pdf += p.base * bottom->pdf(wo, v, TransportMode::Radiance) * (wi.z / (eta * eta * v.z));
    }
    // Refracted in by a delta bottom along d, then the top's own transmission.
    if (p.lobe_t > 0 && !near && refract_travel(-wo, 1 / bottom->relative_eta(), v))
      pdf += p.lobe_t * top.pdf(-v, wi, TransportMode::Radiance);
  }
  return std::isfinite(pdf) ? pdf : Float(0);
}

template <typename C>
BSDFEvalT<C> LayeredBxDFT<C>::eval(const Vec3& wo_in, const Vec3& wi_in, TransportMode mode) const {
  const bool through = transmits();
  if (through) {
    if (wo_in.z == 0 || wi_in.z == 0) return {};
    // Importance mode is the adjoint, f_imp(wo, wi) = f_rad(wi, wo) (SPEC §1), with the
    // density of sampling wi from wo.
    if (mode == TransportMode::Importance) return {eval(wi_in, wo_in, TransportMode::Radiance).f, pdf(wo_in, wi_in, mode)};
  } else if (!(wo_in.z * wi_in.z > 0)) {
    return {};  // the stack reflects only
  }
  // Two-sided when it reflects only: the stack seen from below is mirrored.
  const Float s = through || wo_in.z > 0 ? 1 : -1;
  const Vec3 wo{wo_in.x, wo_in.y, s * wo_in.z}, wi{wi_in.x, wi_in.y, s * wi_in.z};
  const Float pdf = mixture_pdf(mixture(wo), wo, wi);
  // The symmetric estimator: the walk from both ends with one seed, weighted by
  // w(wo, wi) = cos²θi / (cos²θo + cos²θi) and w(wi, wo) (layered.h), so f(wo, wi) =
  // f(wi, wo) exactly (the same two products, and a sum does not depend on its order).
  // Through the stack, the walk from wi estimates f(wi, wo) = (n_wi/n_wo)² f(wo, wi)
  // (Veach 1997, eq. 5.14), so it is scaled by (n_wo/n_wi)².
  // Through the stack the two walks leave through different interfaces, and one that
  // leaves through a rough interface connects by a transmission drawn there, whose
  // direction inside may graze (1/|cos| next to a vertex near it: tails of 800 × the mean,
  // a smooth top over a rough dielectric bottom); the one leaving through a smooth
  // interface has none. So a rough exit's end counts 1/256 as much.
  Float zo2 = wo.z * wo.z, zi2 = wi.z * wi.z;
  if (wo.z * wi.z < 0) {
    if (!interface_delta(wo.z > 0)) zo2 *= Float(1) / 256;
    if (!interface_delta(wi.z > 0)) zi2 *= Float(1) / 256;
  }
  const bool both_tiny = !(zo2 + zi2 > 0);  // squares underflowed: even weights
  const Float wa = both_tiny ? Float(0.5) : zi2 / (zo2 + zi2);
  Float wb = both_tiny ? Float(0.5) : zo2 / (zi2 + zo2);
  if (wo.z * wi.z < 0) {
    const Float eta = relative_eta();
    wb *= wo.z > 0 ? 1 / (eta * eta) : eta * eta;
  }
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
  if (transmits()) {
    if (wo.z == 0 || wi.z == 0) return 0;
    return mixture_pdf(mixture(wo), wo, wi);
  }
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
  const bool through = transmits();
  // Two-sided when it reflects only (the stack seen from below is mirrored).
  const Float s = through || wo_in.z > 0 ? 1 : -1;
  const Vec3 wo{wo_in.x, wo_in.y, s * wo_in.z};
  const Mixture p = mixture(wo);
  Float u = u_lobe;
  Vec3 wi;
  if (u < p.delta + p.delta_t) {
    // The specular chain, estimated with a generator seeded by this sample.
    // (By cos θo alone when isotropic: the chain's weight does not depend on the azimuth.)
    const std::uint64_t where = is_isotropic() ? quantised(wo.z) : direction_hash(wo);
    const std::uint64_t seed = mix64(where ^ mix64(std::uint64_t(std::bit_cast<std::uint32_t>(u1)) << 32 |
                                                   std::bit_cast<std::uint32_t>(u2)));
    const Vec3 mirror{-wo.x, -wo.y, s * wo.z};
    if (!through) return BSDFSampleT<C>{mirror, specular_chain(wo, seed) * (1 / p.delta), p.delta, true, Lobe::Reflection, 1};
    const Chain c = transmitting_chain(wo, mode, seed);
    if (u < p.delta) return BSDFSampleT<C>{mirror, c.reflection * (1 / p.delta), p.delta, true, Lobe::Reflection, 1};
    if (!c.transmitted) return std::nullopt;  // this path's transmission is 0
    const Float eta = wo.z > 0 ? relative_eta() : 1 / relative_eta();
    return BSDFSampleT<C>{c.wt, c.transmission * (1 / p.delta_t), p.delta_t, true, Lobe::Transmission, eta};
  }
  u -= p.delta + p.delta_t;
  const Float eta = geometric_eta();
  if (u < p.lobe) {
    wi = reflect(wo, top.distribution.sample_visible(wo, u1, u2));
    if (!(wi.z > 0)) return std::nullopt;  // below the horizon: no reflection
  } else if ((u -= p.lobe) < p.wide) {
    wi = reflect(wo, widened(top.distribution).sample_visible(wo, u1, u2));
    if (!(wi.z > 0)) return std::nullopt;
  } else if ((u -= p.wide) < p.lobe_t) {
    // A rough top's transmission and a delta bottom's refraction, in the order light meets them.
    const Float ut = std::min(u / p.lobe_t, kOneMinusEpsilon);
    const Float eb = bottom->relative_eta();
    if (wo.z > 0) {
      const auto ts = top.sample(wo, ut, u1, u2, TransportMode::Radiance);
      if (!ts || !(ts->wi.z < 0) || !refract_travel(ts->wi, eb, wi)) return std::nullopt;
    } else {
      Vec3 d;
      if (!refract_travel(-wo, 1 / eb, d)) return std::nullopt;
      const auto ts = top.sample(-d, ut, u1, u2, TransportMode::Radiance);
      if (!ts || !(ts->wi.z > 0)) return std::nullopt;
      wi = ts->wi;
    }
  } else if ((u -= p.lobe_t) < p.base) {
    // The bottom's own sampling: from above at the refracted wo, and back out through
    // the top when it reflects; from below directly, and out through the top when it
    // transmits.
    const Float ub = std::min(u / p.base, kOneMinusEpsilon);
    Vec3 vo = wo;
    if (wo.z > 0 && !refract_in(wo, eta, vo)) return std::nullopt;
    const auto bs = bottom->sample(vo, ub, u1, u2, TransportMode::Radiance);
    if (!bs || bs->delta || bs->wi.z == 0) return std::nullopt;
    if (bs->wi.z > 0) {
      if (!refract_out(bs->wi, eta, wi)) return std::nullopt;
    } else {
      wi = bs->wi;
    }
  } else if ((u -= p.base) < p.medium) {
    Vec3 vo;
    if (!refract_in(wo, eta, vo)) return std::nullopt;
    Vec3 v = hg_sample(-vo, g, u1, u2);
    v.z = std::abs(v.z);  // the mirror at the bottom
    if (!(v.z > 0) || !refract_out(v, eta, wi)) return std::nullopt;
  } else if ((u -= p.medium) < p.cosine) {
    wi = square_to_cosine_hemisphere(u1, u2);
    if (wo.z < 0) wi.z = -wi.z;
  } else {
    wi = square_to_cosine_hemisphere(u1, u2);  // the far side's
    if (wo.z > 0) wi.z = -wi.z;
  }
  if (wi.z == 0) return std::nullopt;
  const BSDFEvalT<C> e = eval(wo, wi, mode);
  if (!(e.pdf > 0)) return std::nullopt;
  const C weight = e.f * (std::abs(wi.z) / e.pdf);
  wi.z *= s;
  const bool reflected = wo.z * wi.z > 0 || s < 0;
  if (reflected) return BSDFSampleT<C>{wi, weight, e.pdf, false, Lobe::Reflection, 1};
  return BSDFSampleT<C>{wi, weight, e.pdf, false, Lobe::Transmission, wo.z > 0 ? relative_eta() : 1 / relative_eta()};
}

}  // namespace gonio
