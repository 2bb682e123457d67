#pragma once
// Fresnel reflectance and the ideal reflection/refraction directions, as free functions
// (templated on the scalar so the CLI can evaluate them in double).
//
// Conventions: `cos_i` is the cosine between the incident direction and the normal of the
// side it arrives from; `eta` is the relative index n_t / n_i of the medium beyond the
// interface over the medium of incidence. For the dielectric functions a negative cos_i
// means the light arrives from the other side of the normal, so eta is inverted
// (SPEC §1: eta = n_inside / n_outside, the normal points outside).

#include <algorithm>
#include <cmath>
#include <optional>
#include <type_traits>

#include "gonio/math/vec3.h"

namespace gonio {

template <typename T>
struct FresnelTerms {
  T rs = 0;        // reflectance for s (TE) polarisation, |r_s|²
  T rp = 0;        // reflectance for p (TM) polarisation, |r_p|²
  T cos_t = 0;     // cosine of the refracted angle (0 under total internal reflection)
  bool tir = false;
  T r() const { return (rs + rp) / 2; }  // unpolarised
};

// The dielectric Fresnel equations (Hecht, Optics, §4.6.2, eqs. 4.34 and 4.40, in the cos
// form after substituting Snell's law n_i sin θi = n_t sin θt, lecture §5.3) from the two
// cosines: c = cos θi > 0 on the side of incidence, ct = cos θt ≥ 0 beyond, e = n_t / n_i.
// The amplitude ratios are r_s = a/b = (c − e ct)/(c + e ct) and r_p = p/d = (e c − ct)/(e c + ct).
// Every quantity below is homogeneous of degree 0 in (c, ct): any common scale of the two
// cosines gives the same reflectance (the rough dielectric passes dot products with an
// unnormalised half vector). This is gonio's one implementation of dielectric Fresnel;
// every other form below and in the models is built on it.
template <typename T>
struct DielectricFresnelParts {
  T a, b, p, d;  // r_s = a/b, r_p = p/d
  T ecct;        // e c ct: b² − a² = d² − p² = 4 e c ct
  T rs() const { return a * a / (b * b); }  // |r_s|²
  T rp() const { return p * p / (d * d); }  // |r_p|²
  // Unpolarised R = (r_s² + r_p²)/2 over one division (1 if the denominators vanish, which
  // needs c = ct = 0: grazing incidence at the critical angle). At grazing incidence
  // r_s = r_p = −1 and the rounded quotient can exceed 1 by an ulp, hence the clamp (1 − R
  // must not turn negative).
  T r() const {
    const T bd = b * d;
    return bd > 0 ? std::min(T(1), (a * a * d * d + p * p * b * b) / (2 * bd * bd)) : T(1);
  }
  // T = 1 − R = 2 e c ct (b² + d²) / (b² d²): no cancellation where R → 1. As a quotient,
  // so that a caller can fold the division into its own.
  T t_numerator() const { return 2 * ecct * (b * b + d * d); }
  T t_denominator() const { return (b * b) * (d * d); }
  T t() const {
    const T den = t_denominator();
    return den > 0 ? t_numerator() / den : T(0);
  }
};

template <typename T>
[[gnu::always_inline]] inline DielectricFresnelParts<T> fresnel_dielectric_parts(T c, T ct, T e) {
  return {c - e * ct, c + e * ct, e * c - ct, e * c + ct, e * c * ct};
}

// cos²θt = 1 − sin²θi / e² for |cos θi| = c (c2 = c²) and inv_e = 1/e; ≤ 0 under total
// internal reflection (SPEC §1: at the critical angle it is total). Written
// c²/e² + (1 − 1/e²): for e ≥ 1 a sum of two non-negative terms, so cos θt keeps its digits
// at grazing incidence onto a nearly index-matched interface (1 − (1 − c²)/e² rounded
// (1 − c²) to 1 for c < 2.4e-4 at e = 1: cos θt = 0 and F = 1 where it is 0).
template <typename T>
[[gnu::always_inline]] inline T dielectric_cos2_t(T c2, T inv_e) {
  const T ie2 = inv_e * inv_e;
  return std::min(c2, T(1)) * ie2 + (1 - ie2);
}

// Unpolarised reflectance for |cos θi| = c (c2 = c²) on the side from which the relative
// index to cross is e (inv_e = 1/e given too): the hot-path entry, 1 under total internal
// reflection.
template <typename T>
[[gnu::always_inline]] inline T fresnel_dielectric_oriented(T c, T c2, T e, T inv_e) {
  const T ct2 = dielectric_cos2_t(c2, inv_e);
  if (!(ct2 > 0)) return T(1);
  return fresnel_dielectric_parts(c, std::sqrt(ct2), e).r();
}

// Dielectric Fresnel terms for light arriving at cos_i (negative: from the other side of
// the normal, eta inverted; SPEC §1: eta = n_inside / n_outside, the normal points outside).
template <typename T>
inline FresnelTerms<T> fresnel_dielectric_terms(T cos_i, T eta) {
  cos_i = std::clamp(cos_i, T(-1), T(1));
  if (cos_i < 0) {
    eta = 1 / eta;
    cos_i = -cos_i;
  }
  const T ct2 = dielectric_cos2_t(cos_i * cos_i, 1 / eta);
  if (!(ct2 > 0)) return {T(1), T(1), T(0), true};
  const T cos_t = std::sqrt(ct2);
  // Both denominators are > 0 here: cos_i = 0 with ct2 > 0 needs eta > 1, so cos_t > 0.
  const auto parts = fresnel_dielectric_parts(cos_i, cos_t, eta);
  return {parts.rs(), parts.rp(), cos_t, false};
}

// Unpolarised dielectric reflectance for light arriving at cos_i (sign as above).
template <typename T>
inline T fresnel_dielectric(T cos_i, T eta) {
  cos_i = std::clamp(cos_i, T(-1), T(1));
  if (cos_i < 0) {
    eta = 1 / eta;
    cos_i = -cos_i;
  }
  return fresnel_dielectric_oriented(cos_i, cos_i * cos_i, eta, 1 / eta);
}

// sqrt lane by lane: std::sqrt for a scalar, each lane of a GCC/Clang vector (which the
// compiler turns into one sqrtps).
template <typename V>
[[gnu::always_inline]] inline V lane_sqrt(V x) {
  if constexpr (std::is_floating_point_v<V>) {
    return std::sqrt(x);
  } else {
    V r;
    for (int i = 0; i < int(sizeof(V) / sizeof(x[0])); ++i) r[i] = std::sqrt(x[i]);
    return r;
  }
}

// Exact Fresnel reflectance of an absorbing medium with complex relative index eta + i k
// (Born & Wolf, Principles of Optics, §14.2; Hecht §4.8). With w = sqrt(η² − sin²θi)
// (principal root, η complex): r_s = (cos θi − w)/(cos θi + w),
// r_p = (η² cos θi − w)/(η² cos θi + w). c = |cos θi| ≤ 1, sin2 = 1 − c². Written once for
// a scalar V (float, double) and for a GCC/Clang vector of floats (one channel per lane,
// conductor.h): only arithmetic, comparisons and ?: selections, which mean the same in both.
//
// w = sqrt(η² − sin²θi) = η cos θt for η² = a + i b: the principal branch (Re w ≥ 0, Im w of
// the sign of b), which for a real η < sin θi (total internal reflection) is
// w = i sqrt(sin²θi − η²), the evanescent wave that decays away from the interface under the
// e^{−iωt} time convention of Born & Wolf (fresnel_amplitudes.h uses it for the phases).
template <typename V>
[[gnu::always_inline]] inline void conductor_w(V sin2, V a, V b, V& wr, V& wi) {
  const V zero{};
  const auto max0 = [zero](V x) { return x > zero ? x : zero; };
  const V zr = a - sin2;
  // |η² − sin²θ|; a plain sqrt, not std::hypot (which guards against overflow at a
  // large cost): indices are bounded to 10⁴, so the squares stay far inside range.
  const V mod = lane_sqrt(zr * zr + b * b);
  wr = lane_sqrt(max0((mod + zr) / 2));
  const V wi_abs = lane_sqrt(max0((mod - zr) / 2));
  wi = b < zero ? -wi_abs : wi_abs;
}

template <typename V>
[[gnu::always_inline]] inline void fresnel_conductor_core(V c, V sin2, V eta, V k, V& rs, V& rp) {
  const V zero{}, one = zero + 1;
  // η² = (n² − k²) + i 2nk
  const V a = eta * eta - k * k;
  const V b = 2 * eta * k;
  V wr, wi;
  conductor_w(sin2, a, b, wr, wi);
  const V s_den = (c + wr) * (c + wr) + wi * wi;
  const V s_num = (c - wr) * (c - wr) + wi * wi;
  const V pr = a * c, pi = b * c;  // η² cos θi
  const V p_den = (pr + wr) * (pr + wr) + (pi + wi) * (pi + wi);
  const V p_num = (pr - wr) * (pr - wr) + (pi - wi) * (pi - wi);
  // A zero denominator only occurs for η = 1, k = 0 at grazing, where there is no
  // interface and the limit of R is 0.
  const V s = s_den > zero ? s_num / (s_den > zero ? s_den : one) : zero;
  const V p = p_den > zero ? p_num / (p_den > zero ? p_den : one) : zero;
  rs = s < one ? s : one;
  rp = p < one ? p : one;
}

// Light arrives from the outside; |cos_i| is used.
template <typename T>
inline FresnelTerms<T> fresnel_conductor_terms(T cos_i, T eta, T k) {
  const T c = std::min(std::abs(cos_i), T(1));
  FresnelTerms<T> t;
  fresnel_conductor_core(c, 1 - c * c, eta, k, t.rs, t.rp);
  return t;
}

template <typename T>
inline T fresnel_conductor(T cos_i, T eta, T k) {
  return fresnel_conductor_terms(cos_i, eta, k).r();
}

// Schlick 1994, eq. 24 (lecture eq. 28): F(θ) = F0 + (1 − F0)(1 − cos θ)^5.
// F0 may be a number or a colour (one F0 per channel); cos θ is clamped to [0, 1], so an
// unnormalised cosine slightly above 1 cannot make (1 − cos θ)^5 negative.
template <typename C, typename T>
inline C fresnel_schlick(const C& f0, T cos_theta) {
  const T m = std::clamp(T(1) - cos_theta, T(0), T(1));
  const T m2 = m * m;
  return f0 + (C(T(1)) - f0) * (m2 * m2 * m);
}

// F82-tint (Hoffman 2023, "Generalization of Adobe's Fresnel Model"; OpenPBR's metal;
// SPEC §2): Schlick's curve with a dip that the tint f82 sets at μ̄ = 1/7 (θ ≈ 82°),
//   F(μ) = F0 + (1 − F0)(1 − μ)⁵ − a μ (1 − μ)⁶,
//   a = S(μ̄) (1 − f82) / (μ̄ (1 − μ̄)⁶),  S(μ̄) = F0 + (1 − F0)(6/7)⁵,  μ̄ (1 − μ̄)⁶ = 6⁶/7⁷,
// so that F(1/7) = f82 S(1/7); clamped to [0, 1] per channel (a small f82 makes the dip
// go below 0 near grazing: for every F0 < 1 at f82 = 0, F0 < 0.057 at f82 = 0.3, F0 <
// 0.001 at f82 = 0.5).
namespace f82_tint {
inline constexpr double kBar5 = 7776.0 / 16807.0;            // (1 − μ̄)⁵ = (6/7)⁵
inline constexpr double kInvDenominator = 823543.0 / 46656.0;  // 1/(μ̄ (1 − μ̄)⁶) = 7⁷/6⁶
// a = (1 − f82) (S̄0 + S̄1 F0): S(μ̄)/(μ̄ (1 − μ̄)⁶) expanded in F0, its two constants
// folded in double; a few multiplies, no division. V is Float or a GCC vector of Floats.
inline constexpr Float kS0 = Float(kBar5 * kInvDenominator), kS1 = Float((1 - kBar5) * kInvDenominator);
template <typename V>
inline V a(V f0, V f82) {
  return (Float(1) - f82) * (kS0 + kS1 * f0);
}
}  // namespace f82_tint
template <typename C>
inline C fresnel_f82_a(const C& f0, const C& f82) {
  C a;
  for (int i = 0; i < C::size(); ++i) a[i] = f82_tint::a(f0[i], f82[i]);
  return a;
}
// F(μ) given a = fresnel_f82_a(f0, f82), which depends on the material alone: computed
// once when it is made (ConductorFresnelT::prepare), F82-tint costs Schlick plus a
// multiply-subtract and the clamp per channel.
template <typename C, typename T>
inline C fresnel_f82_from_a(const C& f0, const C& a, T cos_theta) {
  const T mu = std::clamp(cos_theta, T(0), T(1));
  // F0 + (1 − F0)(1 − μ)⁵ − a μ (1 − μ)⁶ = F0 + (1 − μ)⁵ ((1 − F0) − a μ (1 − μ)).
  const T m = 1 - mu, m2 = m * m, m5 = m2 * m2 * m, w = mu * m;
  C f;
  for (int i = 0; i < C::size(); ++i)
    f[i] = std::min(std::max(f0[i] + m5 * ((1 - f0[i]) - a[i] * w), Float(0)), Float(1));
  return f;
}
template <typename C, typename T>
inline C fresnel_f82(const C& f0, const C& f82, T cos_theta) {
  return fresnel_f82_from_a(f0, fresnel_f82_a(f0, f82), cos_theta);
}
// Its hemispherical average 2∫F μ dμ without the clamp (SPEC §2; Beta integrals:
// 2∫(1 − μ)⁵ μ dμ = 1/21, 2∫μ² (1 − μ)⁶ dμ = 1/126): (20 F0 + 1)/21 − a/126. Exact
// wherever F stays within [0, 1]; where the clamp acts (above) it is below the clamped
// F's average, as SPEC §2 fixes it, and kept from going negative.
template <typename C>
inline C fresnel_f82_average(const C& f0, const C& f82) {
  C avg = (f0 * Float(20) + C(Float(1))) * Float(1.0 / 21) - fresnel_f82_a(f0, f82) * Float(1.0 / 126);
  for (int i = 0; i < C::size(); ++i) avg[i] = std::max(avg[i], Float(0));
  return avg;
}

// F0 = |(η − 1)/(η + 1)|² at normal incidence, for eta + i k (k = 0: a dielectric).
template <typename T>
inline T fresnel_f0(T eta, T k = T(0)) {
  return ((eta - 1) * (eta - 1) + k * k) / ((eta + 1) * (eta + 1) + k * k);
}

// Schlick for a dielectric seen from the outside at cos θ onto relative index eta, as
// SPEC §3 fixes it: the cosine on the denser side enters the formula, i.e. cos θ for
// eta ≥ 1 and cos θt for eta < 1, and 1 under total internal reflection.
template <typename T>
inline T fresnel_schlick_dielectric(T cos_i, T eta) {
  const T f0 = fresnel_f0(eta);
  cos_i = std::clamp(std::abs(cos_i), T(0), T(1));
  if (eta >= 1) return fresnel_schlick(f0, cos_i);
  const T sin2_t = (1 - cos_i * cos_i) / (eta * eta);
  if (sin2_t >= 1) return T(1);
  return fresnel_schlick(f0, std::sqrt(1 - sin2_t));
}

// The terms `gonio fresnel` and the Python module report for light from the outside at
// cos_i onto eta + i k: a conductor's (Born & Wolf) when k > 0, else a dielectric's
// (Hecht), and Schlick's approximation of the same interface (SPEC §3: the rule of
// fresnel_schlick_dielectric for k = 0, F0 = fresnel_f0(eta, k) for a conductor).
template <typename T>
inline FresnelTerms<T> fresnel_terms(T cos_i, T eta, T k) {
  return k > 0 ? fresnel_conductor_terms(cos_i, eta, k) : fresnel_dielectric_terms(cos_i, eta);
}
template <typename T>
inline T fresnel_schlick_terms(T cos_i, T eta, T k) {
  return k > 0 ? fresnel_schlick(fresnel_f0(eta, k), std::abs(cos_i)) : fresnel_schlick_dielectric(cos_i, eta);
}

// Mirror reflection about n (lecture §5.2: R = I − 2(I·N)N for I pointing at the surface;
// here wo points away from it, so the result is −wo + 2(wo·n)n).
inline Vec3 reflect(const Vec3& wo, const Vec3& n) { return -wo + n * (2 * dot(wo, n)); }

struct Refraction {
  Vec3 wt;      // refracted direction, pointing away from the surface on the far side
  Float eta;    // relative index n_t / n_i actually crossed (inverted if wi was inside)
};

// Refraction by Snell's law (lecture §5.3): wt = −wi/η + (cos θi/η − cos θt) n for wi on
// the side n points to, η = n_t / n_i. If wi is on the other side, n and η are flipped.
// Returns nothing under total internal reflection (sin²θt ≥ 1).
inline std::optional<Refraction> refract(const Vec3& wi, Vec3 n, Float eta) {
  Float cos_i = dot(n, wi);
  if (cos_i < 0) {
    eta = 1 / eta;
    cos_i = -cos_i;
    n = -n;
  }
  const Float sin2_t = std::max(Float(0), 1 - cos_i * cos_i) / (eta * eta);
  if (sin2_t >= 1) return std::nullopt;
  const Float cos_t = std::sqrt(1 - sin2_t);
  return Refraction{-wi / eta + n * (cos_i / eta - cos_t), eta};
}

}  // namespace gonio
