#pragma once
// Thin dielectric sheet (a window pane; OpenPBR's thin-walled transmission): two parallel
// smooth interfaces of relative index eta with the same medium on both sides, every
// internal reflection summed incoherently (the sheet is many wavelengths thick). With r the
// single interface's reflectance of one polarization and t = 1 − r (Stokes: t t' = 1 − r²,
// r' = r), the light reflected after 2k − 1 internal reflections is t² r^(2k−1), so
//   R = r + t² r / (1 − r²) = 2r / (1 + r),   T = t² / (1 − r²) = (1 − r) / (1 + r) = 1 − R
// per polarization (s and p separately, then averaged: the geometric series of the
// average is not the average of the series). Transmission goes straight through
// (wi = −wo, the two refractions cancel); the sheet does not change the medium, so no
// (n_wo/n_wi)² scaling in either transport mode and relative_eta() = 1. pbrt-v4's
// ThinDielectricBxDF and Mitsuba 3's thindielectric model the same two delta lobes.
//
// Polarized mode (C = MuellerT<colour>): each path is one Jones matrix diagonal in s/p,
// and the paths add incoherently, so each lobe's Mueller matrix is the sum of the paths'
// (mueller.h: mueller_diagonal_jones). With real amplitudes r_s, r_p of the outer face
// (the inner face has r' = −r, t t' = 1 − r², Born & Wolf §1.6.4, Stokes relations) and
// x = r_s r_p, G = (1 − R_s)(1 − R_p):
//   reflection:   M00 ± M01 = R_s^tot, R_p^tot;  M22 = M33 = x + G x / (1 − x²)
//                 (path 0: x; path k ≥ 1: G x^(2k−1)),
//   transmission: M00 ± M01 = T_s^tot, T_p^tot;  M22 = M33 = G / (1 − x²)
//                 (path k ≥ 0: G x^(2k)),
// M23 = M32 = 0 (all amplitudes real outside total internal reflection). At normal
// incidence x = −r², and M22 = −M00 (reflection), +M00 (transmission): no polarization.
// Under total internal reflection at the first face (eta < 1) the sheet is that face's
// total reflection.

#include <cmath>
#include <optional>
#include <string_view>

#include "gonio/bxdf/contract.h"
#include "gonio/bxdf/thin_film.h"
#include "gonio/fresnel.h"
#include "gonio/polarization/fresnel_factor.h"
#include "gonio/polarization/interface.h"

namespace gonio {

// The sheet's reflectance and transmittance per polarization (R + T = 1 for each), and
// the Mueller terms M22 of both lobes, at |cos θ| = c onto relative index eta.
template <typename T>
struct ThinSheetTerms {
  T Rs = 1, Rp = 1, Ts = 0, Tp = 0;
  T m22_r = 0, m22_t = 0;
  bool tir = true;
  T r() const { return (Rs + Rp) / 2; }
  T t() const { return (Ts + Tp) / 2; }
};

template <typename T>
inline ThinSheetTerms<T> thin_sheet_terms(T c, T eta) {
  ThinSheetTerms<T> out;
  c = std::min(std::abs(c), T(1));
  const T ct2 = dielectric_cos2_t(c * c, 1 / eta);
  if (!(ct2 > 0)) return out;  // total internal reflection at the first face
  const auto f = fresnel_dielectric_parts(c, std::sqrt(ct2), eta);  // fresnel.h: r_s = a/b, r_p = p/d
  // 2 r/(1 + r) and (1 − r)/(1 + r) with r = a²/b², 1 − r = 4 e c ct / b² (no cancellation):
  // R_s = 2a² / (a² + b²), T_s = 4 e c ct / (a² + b²); the same with p, d for p.
  const T s_den = f.a * f.a + f.b * f.b, p_den = f.p * f.p + f.d * f.d;
  if (!(s_den > 0) || !(p_den > 0)) return out;
  out.Rs = 2 * f.a * f.a / s_den;
  out.Rp = 2 * f.p * f.p / p_den;
  out.Ts = 4 * f.ecct / s_den;
  out.Tp = 4 * f.ecct / p_den;
  // Mueller M22 sums (top of the file), x = r_s r_p, G = (1 − R_s)(1 − R_p).
  const T x = (f.a / f.b) * (f.p / f.d);
  const T g = (4 * f.ecct / (f.b * f.b)) * (4 * f.ecct / (f.d * f.d));
  const T one_x2 = 1 - x * x;
  const T series = one_x2 > 0 ? g / one_x2 : T(0);
  out.m22_r = x + series * x;
  out.m22_t = series;
  out.tir = false;
  return out;
}

// The Mueller matrices (s/p basis of the plane of incidence, mueller.h) of the two lobes.
template <typename T>
MuellerT<T> thin_sheet_mueller(const ThinSheetTerms<T>& s, bool reflection, T c, T eta) {
  if (s.tir) return reflection ? dielectric_reflection_mueller(std::abs(c), eta) : MuellerT<T>{};
  MuellerT<T> m;
  const T a = reflection ? s.Rs : s.Ts, b = reflection ? s.Rp : s.Tp;
  m(0, 0) = m(1, 1) = (a + b) / 2;
  m(0, 1) = m(1, 0) = (a - b) / 2;
  m(2, 2) = m(3, 3) = reflection ? s.m22_r : s.m22_t;
  return m;
}

template <typename C>
struct ThinDielectricBxDFT {
  using color_type = C;
  static constexpr std::string_view kName = "thindielectric";
  Float eta = 1.5f;  // n_sheet / n_outside (the same medium on both sides)
  // With a thin film the sheet is that one coherent film (SPEC §2, the soap bubble):
  // R = Airy(outside | film | outside) per channel, T = 1 − R; eta is then unused.
  ThinFilmT<Unpolarized<C>> film{};

  static constexpr BxDFFlags flags() {
    return BxDFFlags::SpecularReflection | BxDFFlags::SpecularTransmission;
  }
  // The sheet does not change the medium: transmission continues in the medium of wo.
  static constexpr Float relative_eta() { return 1; }
  C f(const Vec3&, const Vec3&, TransportMode = TransportMode::Radiance) const { return {}; }
  Float pdf(const Vec3&, const Vec3&, TransportMode = TransportMode::Radiance) const { return 0; }

  // u_lobe < R chooses reflection; each lobe's weight is its share over its probability,
  // 1, in both transport modes (same medium on both sides: no radiance scaling).
  std::optional<BSDFSampleT<C>> sample(const Vec3& wo, Float u_lobe, Float, Float,
                                       TransportMode = TransportMode::Radiance) const {
    if (wo.z == 0) return std::nullopt;
    const Float c = std::abs(wo.z);
    if (film.active()) return sample_film(wo, c, u_lobe);
    const ThinSheetTerms<Float> s = thin_sheet_terms(c, eta);
    const Float r = s.r();
    const bool reflect = u_lobe < r;
    const Vec3 wi = reflect ? Vec3{-wo.x, -wo.y, wo.z} : -wo;
    const C w = fresnel_factor<C>(
        Float(1), [&] { return broadcast<Unpolarized<C>>(thin_sheet_mueller(s, reflect, c, eta)); }, wo, wi);
    return BSDFSampleT<C>{wi, w, reflect ? r : s.t(), true, reflect ? Lobe::Reflection : Lobe::Transmission, 1};
  }

  DirectionalAlbedoT<C> albedo(const Vec3& wo, TransportMode = TransportMode::Radiance) const {
    if (wo.z == 0) return {};
    if (film.active()) {
      using U = Unpolarized<C>;
      const U r = film.reflectance(std::min(std::abs(wo.z), Float(1)), U(1), U(0));
      return {C(r), C(U(1) - r)};
    }
    const ThinSheetTerms<Float> s = thin_sheet_terms(std::abs(wo.z), eta);
    return {C(s.r()), C(s.t())};
  }

 private:
  // The soap bubble: the lobe chosen by the channel average of R, each channel weighted by
  // its share over that probability; the same from both sides (a symmetric film).
  std::optional<BSDFSampleT<C>> sample_film(const Vec3& wo, Float c, Float u_lobe) const {
    using U = Unpolarized<C>;
    c = std::min(c, Float(1));
    const U r = film.reflectance(c, U(1), U(0));
    const Float p = std::clamp(r.average(), Float(0), Float(1));
    const bool reflect = u_lobe < p;
    const Vec3 wi = reflect ? Vec3{-wo.x, -wo.y, wo.z} : -wo;
    const U value = reflect ? r / p : (U(1) - r) / (1 - p);
    const C w = fresnel_factor<C>(value, [&] { return film.mueller(c, U(1), U(0), reflect, false); }, wo, wi);
    return BSDFSampleT<C>{wi, w, reflect ? p : 1 - p, true, reflect ? Lobe::Reflection : Lobe::Transmission, 1};
  }
};

using ThinDielectricBxDF = ThinDielectricBxDFT<Color>;

}  // namespace gonio
