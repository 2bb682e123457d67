#pragma once
// Mueller matrices of reflection and transmission at a plane interface, in the s/p basis
// of the plane of incidence (polarization/mueller.h for the conventions), from the complex
// amplitudes of fresnel_amplitudes.h. Their M00 and M01 are taken from fresnel.h's scalar
// reflectances, so that M00 is exactly gonio's unpolarized Fresnel factor.
//   Reflection:   Jones diag(r_s, r_p): M00 = R = (R_s + R_p)/2, M01 = M10 = (R_s − R_p)/2,
//                 M22 = M33 = Re(r_s r_p*), M32 = −M23 = Im(r_s r_p*)
//                 (Born & Wolf §1.5.2 and §1.4.2; e.g. Collett, Field Guide to
//                 Polarization, 2005, "Mueller matrices for reflection and transmission").
//   Transmission: the transmitted power fractions, Jones diag(t_s, t_p) times the factor
//                 n_t cos θt / (n_i cos θi): M00 = T = 1 − R, M01 = M10 = (T_s − T_p)/2 with
//                 T_s = 1 − R_s, T_p = 1 − R_p (each in fresnel.h's cancellation-free form,
//                 which keeps the matrix realizable at grazing incidence, where 1 − R
//                 rounded lost the digits that M22 has), M22 = M33 = factor Re(t_s t_p*) (t real
//                 outside total internal reflection, which transmits nothing).

#include "gonio/fresnel_amplitudes.h"
#include "gonio/polarization/mueller.h"

namespace gonio {

template <typename T>
MuellerT<T> mueller_reflection(const FresnelAmplitudes<T>& a) {
  MuellerT<T> m = mueller_diagonal_jones(a.rs, a.rp);
  m(0, 0) = m(1, 1) = a.R;
  m(0, 1) = m(1, 0) = (a.Rs - a.Rp) / 2;
  return m;
}

template <typename T>
MuellerT<T> mueller_transmission(const FresnelAmplitudes<T>& a) {
  if (a.tir || !(a.t_factor > 0)) return {};
  MuellerT<T> m = mueller_diagonal_jones(a.ts, a.tp);
  for (int r = 2; r < 4; ++r)
    for (int c = 2; c < 4; ++c) m(r, c) *= a.t_factor;
  m(0, 0) = m(1, 1) = a.T_;
  m(0, 1) = m(1, 0) = (a.Ts - a.Tp) / 2;
  return m;
}

// The two for a dielectric of relative index eta, light arriving at cos_i (sign as in
// fresnel_dielectric_amplitudes).
template <typename T>
MuellerT<T> dielectric_reflection_mueller(T cos_i, T eta) {
  return mueller_reflection(fresnel_dielectric_amplitudes(cos_i, eta));
}
template <typename T>
MuellerT<T> dielectric_transmission_mueller(T cos_i, T eta) {
  return mueller_transmission(fresnel_dielectric_amplitudes(cos_i, eta));
}

}  // namespace gonio
