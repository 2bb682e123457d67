#pragma once
// Complex Fresnel amplitude ratios r_s, r_p, t_s, t_p (issue 15), built on gonio's one
// Fresnel (fresnel.h): the dielectric amplitudes are the quotients of
// fresnel_dielectric_parts, the conductor's and those under total internal reflection use
// its principal root w = η cos θt (conductor_w); |r|² is left to the scalar functions there,
// which these results carry unchanged (Rs, Rp, R), so that the unpolarized quantities stay
// exactly what they were.
//
// Sign convention (Born & Wolf, Principles of Optics, 7th ed., §1.5.2 eqs. 20–21; Hecht,
// Optics, 4th ed., eqs. 4.34, 4.40–4.42 agree in the cos form used here), with time
// dependence e^{−iωt} and complex index η = n + i k (k ≥ 0 absorbs):
//   r_s = (cos θi − w)/(cos θi + w),           t_s = 2 cos θi / (cos θi + w),
//   r_p = (η² cos θi − w)/(η² cos θi + w),     t_p = 2 η cos θi / (η² cos θi + w),
//   w = η cos θt = sqrt(η² − sin²θi),
// the p components taken along p = k × s for every wave (k its direction of propagation,
// s one common unit vector perpendicular to the plane of incidence): at normal incidence
// r_p = −r_s, at grazing incidence r_s = r_p = −1. docs/polarization.md derives it.

#include <cmath>
#include <complex>

#include "gonio/fresnel.h"

namespace gonio {

template <typename T>
struct FresnelAmplitudes {
  std::complex<T> rs, rp;  // reflected / incident amplitude, s and p
  std::complex<T> ts, tp;  // transmitted / incident amplitude (0 for a conductor)
  T Rs = 0, Rp = 0, R = 0;  // |r_s|², |r_p|² and (|r_s|² + |r_p|²)/2 from fresnel.h's scalar code
  // Dielectric transmittances 1 − R_s, 1 − R_p, 1 − R without cancellation where R → 1
  // (4 e c ct / b², 4 e c ct / d², DielectricFresnelParts::t()); 0 for a conductor.
  T Ts = 0, Tp = 0, T_ = 0;
  // Power transmission factor Re(w) / cos θi = n_t cos θt / (n_i cos θi): T_s = factor |t_s|²
  // (0 under total internal reflection and for a conductor, whose T is absorbed).
  T t_factor = 0;
  bool tir = false;
};

// Dielectric of relative index eta, light arriving at cos_i (negative: from the other side
// of the normal, eta inverted; as fresnel_dielectric_terms).
template <typename T>
inline FresnelAmplitudes<T> fresnel_dielectric_amplitudes(T cos_i, T eta) {
  using Cx = std::complex<T>;
  cos_i = std::clamp(cos_i, T(-1), T(1));
  if (cos_i < 0) {
    eta = 1 / eta;
    cos_i = -cos_i;
  }
  const T c = cos_i;
  FresnelAmplitudes<T> out;
  const T ct2 = dielectric_cos2_t(c * c, 1 / eta);
  if (ct2 > 0) {
    const T ct = std::sqrt(ct2);
    const auto parts = fresnel_dielectric_parts(c, ct, eta);  // b, d > 0 here (fresnel.h)
    out.rs = Cx(parts.a / parts.b);
    out.rp = Cx(parts.p / parts.d);
    out.ts = Cx(2 * c / parts.b);
    out.tp = Cx(2 * c / parts.d);
    out.Rs = parts.rs();
    out.Rp = parts.rp();
    out.R = parts.r();
    out.Ts = 4 * parts.ecct / (parts.b * parts.b);
    out.Tp = 4 * parts.ecct / (parts.d * parts.d);
    out.T_ = parts.t();
    out.t_factor = c > 0 ? eta * ct / c : T(0);
    return out;
  }
  // Total internal reflection: w = i γ, γ = sqrt(sin²θi − η²) (conductor_w with b = 0).
  T wr, wi;
  conductor_w(T(1) - c * c, eta * eta, T(0), wr, wi);
  const Cx w(wr, wi), e2(eta * eta);
  const Cx s_den = c + w, p_den = e2 * c + w;
  // Both vanish only at grazing incidence exactly at the critical angle (c = γ = 0), where
  // the limit is that of grazing incidence, r = −1.
  out.rs = std::norm(s_den) > 0 ? (c - w) / s_den : Cx(-1);
  out.rp = std::norm(p_den) > 0 ? (e2 * c - w) / p_den : Cx(-1);
  out.ts = std::norm(s_den) > 0 ? Cx(2 * c) / s_den : Cx(0);
  out.tp = std::norm(p_den) > 0 ? Cx(2 * eta * c) / p_den : Cx(0);
  out.Rs = out.Rp = out.R = 1;
  out.tir = true;
  return out;
}

// Conductor of complex relative index eta + i k, light arriving from the outside (|cos_i|).
template <typename T>
inline FresnelAmplitudes<T> fresnel_conductor_amplitudes(T cos_i, T eta, T k) {
  using Cx = std::complex<T>;
  const T c = std::min(std::abs(cos_i), T(1));
  FresnelAmplitudes<T> out;
  const FresnelTerms<T> terms = fresnel_conductor_terms(cos_i, eta, k);
  out.Rs = terms.rs;
  out.Rp = terms.rp;
  out.R = terms.r();
  const T a = eta * eta - k * k, b = 2 * eta * k;  // η², as in fresnel_conductor_core
  T wr, wi;
  conductor_w(T(1) - c * c, a, b, wr, wi);
  const Cx w(wr, wi), e2(a, b);
  const Cx s_den = c + w, p_den = e2 * c + w;
  // A zero denominator needs η = 1, k = 0 at grazing: no interface, r = 0 (fresnel.h).
  out.rs = std::norm(s_den) > 0 ? (c - w) / s_den : Cx(0);
  out.rp = std::norm(p_den) > 0 ? (e2 * c - w) / p_den : Cx(0);
  return out;
}

}  // namespace gonio
