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

// Exact dielectric Fresnel equations (Hecht, Optics, §4.6.2, eqs. 4.34 and 4.40, in the
// cos form after substituting Snell's law n_i sin θi = n_t sin θt, lecture §5.3).
// Total internal reflection when sin²θt ≥ 1 (SPEC §1: at the critical angle it is total).
template <typename T>
inline FresnelTerms<T> fresnel_dielectric_terms(T cos_i, T eta) {
  cos_i = std::clamp(cos_i, T(-1), T(1));
  if (cos_i < 0) {
    eta = 1 / eta;
    cos_i = -cos_i;
  }
  const T sin2_t = (1 - cos_i * cos_i) / (eta * eta);
  if (sin2_t >= 1) return {T(1), T(1), T(0), true};
  const T cos_t = std::sqrt(1 - sin2_t);
  // Both denominators are > 0 here: cos_i = 0 with sin2_t < 1 needs eta > 1, so cos_t > 0.
  const T rs = (cos_i - eta * cos_t) / (cos_i + eta * cos_t);
  const T rp = (eta * cos_i - cos_t) / (eta * cos_i + cos_t);
  return {rs * rs, rp * rp, cos_t, false};
}

// Unpolarised dielectric reflectance; the hot-path form of fresnel_dielectric_terms.
template <typename T>
inline T fresnel_dielectric(T cos_i, T eta) {
  cos_i = std::clamp(cos_i, T(-1), T(1));
  if (cos_i < 0) {
    eta = 1 / eta;
    cos_i = -cos_i;
  }
  const T sin2_t = (1 - cos_i * cos_i) / (eta * eta);
  if (sin2_t >= 1) return T(1);
  const T cos_t = std::sqrt(1 - sin2_t);
  const T rs = (cos_i - eta * cos_t) / (cos_i + eta * cos_t);
  const T rp = (eta * cos_i - cos_t) / (eta * cos_i + cos_t);
  return (rs * rs + rp * rp) / 2;
}

// Exact Fresnel reflectance of an absorbing medium with complex relative index eta + i k
// (Born & Wolf, Principles of Optics, §14.2; Hecht §4.8). With w = sqrt(η² − sin²θi)
// (principal root, η complex): r_s = (cos θi − w)/(cos θi + w),
// r_p = (η² cos θi − w)/(η² cos θi + w). Light arrives from the outside; |cos_i| is used.
template <typename T>
inline FresnelTerms<T> fresnel_conductor_terms(T cos_i, T eta, T k) {
  const T c = std::min(std::abs(cos_i), T(1));
  const T sin2 = 1 - c * c;
  // η² = (n² − k²) + i 2nk
  const T a = eta * eta - k * k;
  const T b = 2 * eta * k;
  // w = sqrt((a − sin²θ) + i b), principal branch (Re w ≥ 0, Im w ≥ 0 since b ≥ 0).
  const T zr = a - sin2;
  // |η² − sin²θ|; a plain sqrt, not std::hypot (which guards against overflow at a
  // large cost): indices are bounded to 10⁴, so the squares stay far inside range.
  const T mod = std::sqrt(zr * zr + b * b);
  const T wr = std::sqrt(std::max(T(0), (mod + zr) / 2));
  const T wi = std::copysign(std::sqrt(std::max(T(0), (mod - zr) / 2)), b);
  const T s_den = (c + wr) * (c + wr) + wi * wi;
  const T rs = s_den > 0 ? ((c - wr) * (c - wr) + wi * wi) / s_den : T(0);
  const T pr = a * c, pi = b * c;  // η² cos θi
  const T p_den = (pr + wr) * (pr + wr) + (pi + wi) * (pi + wi);
  const T rp = p_den > 0 ? ((pr - wr) * (pr - wr) + (pi - wi) * (pi - wi)) / p_den : T(0);
  // A zero denominator only occurs for η = 1, k = 0 at grazing, where there is no
  // interface and the limit of R is 0.
  return {std::min(rs, T(1)), std::min(rp, T(1)), T(0), false};
}

template <typename T>
inline T fresnel_conductor(T cos_i, T eta, T k) {
  return fresnel_conductor_terms(cos_i, eta, k).r();
}

// Schlick 1994, eq. 24 (lecture eq. 28): F(θ) = F0 + (1 − F0)(1 − cos θ)^5.
template <typename T>
inline T fresnel_schlick(T f0, T cos_theta) {
  const T m = std::clamp(1 - cos_theta, T(0), T(1));
  const T m2 = m * m;
  return f0 + (1 - f0) * (m2 * m2 * m);
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
