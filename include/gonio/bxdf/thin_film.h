#pragma once
// A thin film on an interface (issue 34; SPEC §2 "thin_film"): a layer of index n_f and
// thickness d (nanometres) on the outside (z > 0) face. Its two interfaces' amplitudes are
// summed coherently, the Airy summation of Belcour & Barla 2017 ("A Practical Extension to
// Microfacet Theory for the Modeling of Varying Iridescence", ACM TOG 36(4), eq. 1; Born &
// Wolf §1.6.4 eq. 57), per polarization and per wavelength λ:
//   r = (r12 + r23 e^{iΔ}) / (1 + r12 r23 e^{iΔ}),   Δ = (2π/λ) 2 n_f d cos θ_f,
// with r12 the outside/film amplitude at cos θ1 and r23 the film/substrate amplitude at
// cos θ_f (Snell: n_f sin θ_f = sin θ1), both from gonio's one Fresnel
// (fresnel_amplitudes.h, Born & Wolf's convention, e^{−iωt}: the film's round trip adds
// +Δ). A conductor substrate's r23 is complex (relative index (n + ik)/n_f), which carries
// its phase shift (Belcour & Barla's φ23). R = |r|². The film is lossless (n_f real, ≥ 1
// so that it never totally reflects light from the outside), so T = 1 − R for a
// dielectric substrate, and the film never changes directions: refraction uses the
// substrate's own index. Light from inside a dielectric substrate at the corresponding
// angle sees r' = (r32 + r21 e^{iΔ}) / (1 + r32 r21 e^{iΔ}) = −(r23 + r12 e^{iΔ}) / (1 +
// r12 r23 e^{iΔ}) (Stokes: r21 = −r12), of the same modulus: R is the same from both
// sides, T as well.
//
// Per colour type: spectral mode evaluates the Airy sum exactly at each wavelength of the
// path (`lambda`); RGB mode reads R from a table over cos θ1 precomputed per material
// (ThinFilmRgbTable: the reflectance spectrum reduced to linear sRGB under D65 exactly as
// `gonio spectrum` reduces a reflectance). Polarized mode: the Jones matrix diag(r_s, r_p)
// (reflection) or diag(t_s, t_p) (transmission) in Mueller form, exact per wavelength in
// spectral mode; in RGB mode its shape is that at the channel's wavelength (650, 550,
// 450 nm, as an index), scaled to the tabulated R (fresnel_factor.h).

#include <algorithm>
#include <cmath>
#include <complex>
#include <functional>
#include <memory>
#include <type_traits>
#include <utility>
#include <vector>

#include "gonio/color.h"
#include "gonio/fresnel.h"
#include "gonio/fresnel_amplitudes.h"
#include "gonio/math/constants.h"
#include "gonio/polarization/mueller.h"
#include "gonio/spectrum/spectrum_to_rgb.h"

namespace gonio {

template <typename T>
struct FilmAmplitudes {
  std::complex<T> rs, rp;   // reflected / incident amplitude, from the side asked
  std::complex<T> ts, tp;   // transmitted amplitude up to the common factor e^{iΔ/2} (dielectric substrate)
  T Rs = 0, Rp = 0;         // |r_s|², |r_p|²
  T R() const { return (Rs + Rp) / 2; }
};

// Light from the outside (index 1) at cos1 ∈ [0, 1] onto a film of index nf (≥ 1) and
// thickness d over a substrate of relative index n3 + i k3, at wavelength lambda (d and
// lambda in the same unit). back: the reflection seen from inside a dielectric substrate,
// at the angle that corresponds to cos1 (top of the file).
template <typename T>
FilmAmplitudes<T> airy_film(T cos1, T nf, T d, T n3, T k3, T lambda, bool back = false) {
  using Cx = std::complex<T>;
  const T c1 = std::clamp(cos1, T(0), T(1));
  const FresnelAmplitudes<T> a12 = fresnel_dielectric_amplitudes(c1, nf);
  const T c2 = std::sqrt(std::max(T(0), dielectric_cos2_t(c1 * c1, 1 / nf)));
  const FresnelAmplitudes<T> a23 =
      k3 > 0 ? fresnel_conductor_amplitudes(c2, n3 / nf, k3 / nf) : fresnel_dielectric_amplitudes(c2, n3 / nf);
  // Belcour & Barla 2017, eq. 1 (its OPD 2 n_f d cos θ_f, §3): the round trip's phase.
  const T delta = T(4 * kPiD) * nf * d * c2 / lambda;
  const Cx e = std::polar(T(1), delta);
  FilmAmplitudes<T> out;
  const Cx ds = T(1) + a12.rs * a23.rs * e, dp = T(1) + a12.rp * a23.rp * e;
  // |1 + r12 r23 e| ≥ 1 − |r12 r23| > 0 unless both faces reflect totally (grazing).
  const bool ok_s = std::norm(ds) > 0, ok_p = std::norm(dp) > 0;
  if (back) {
    out.rs = ok_s ? -(a23.rs + a12.rs * e) / ds : Cx(-1);
    out.rp = ok_p ? -(a23.rp + a12.rp * e) / dp : Cx(-1);
  } else {
    out.rs = ok_s ? (a12.rs + a23.rs * e) / ds : Cx(-1);
    out.rp = ok_p ? (a12.rp + a23.rp * e) / dp : Cx(-1);
  }
  // Airy's transmitted sum t12 t23 e^{iΔ/2} / (1 + r12 r23 e^{iΔ}); the common phase
  // factor cancels in t_s t_p*, the only product the Mueller matrix needs.
  out.ts = ok_s ? a12.ts * a23.ts / ds : Cx(0);
  out.tp = ok_p ? a12.tp * a23.tp / dp : Cx(0);
  out.Rs = std::min(T(1), std::norm(out.rs));
  out.Rp = std::min(T(1), std::norm(out.rp));
  return out;
}

// Mueller matrices (s/p basis, mueller.h) of a film's reflection and of the transmission
// of a lossless stack: M00 ± M01 = R_s, R_p (or T_s = 1 − R_s, T_p = 1 − R_p), the
// off-diagonal block from r_s r_p* (t_s t_p*, whose modulus is set to sqrt(T_s T_p): the
// transmitted power, without the power factors of the two media).
template <typename T>
MuellerT<T> film_reflection_mueller(const FilmAmplitudes<T>& a) {
  MuellerT<T> m = mueller_diagonal_jones(a.rs, a.rp);
  m(0, 0) = m(1, 1) = a.R();
  m(0, 1) = m(1, 0) = (a.Rs - a.Rp) / 2;
  return m;
}
template <typename T>
MuellerT<T> film_transmission_mueller(const FilmAmplitudes<T>& a) {
  const T ts = 1 - a.Rs, tp = 1 - a.Rp;
  MuellerT<T> m;
  m(0, 0) = m(1, 1) = (ts + tp) / 2;
  m(0, 1) = m(1, 0) = (ts - tp) / 2;
  const std::complex<T> z = a.ts * std::conj(a.tp);
  const T mod = std::abs(z);
  if (mod > 0) {
    const std::complex<T> u = z * (std::sqrt(std::max(T(0), ts * tp)) / mod);
    m(2, 2) = m(3, 3) = u.real();
    m(2, 3) = -u.imag();
    m(3, 2) = u.imag();
  }
  return m;
}

// RGB mode's reflectance of one film on one substrate, R(cos θ1) reduced to linear sRGB,
// at kEntries points evenly spaced in x = sqrt((cos²θ1 − c0²) / (1 − c0²)), linearly
// interpolated. c0 is the cosine of the substrate's critical angle seen from outside
// (c0² = 1 − n² for a substrate of real index n < 1, else 0): R rises to 1 there like a
// square root of cos²θ1 − c0², which is linear in x, so the interpolation does not round
// off the kink (below c0 the models return R = 1 exactly, film_read_cos). The largest
// interpolation error, from 100 nm to 2 µm on glass and on a metal, is 8.6e-4
// (ThinFilm.RgbTableInterpolationError prints it). Made once per material
// (src/spectrum/thin_film_table.cpp).
struct ThinFilmRgbTable {
  static constexpr int kEntries = 513;
  Float c0 = 0;
  std::vector<Color> r;  // kEntries entries
  // The substrate's (n, k) at every nanometre the reduction read, from kCieFirstNm: the
  // table's input, kept for the validator's own closed form (src/validate).
  std::vector<std::pair<double, double>> substrate;
  // The cosine of entry i (x = i / (kEntries − 1)).
  double cos_of(int i) const {
    const double x = double(i) / (kEntries - 1), c02 = double(c0) * c0;
    return std::sqrt(c02 + x * x * (1 - c02));
  }
  Color lookup(Float cos1) const {
    const Float c = std::clamp(cos1, Float(0), Float(1));
    const Float x2 = c0 > 0 ? std::max(Float(0), (c * c - c0 * c0) / (1 - c0 * c0)) : c * c;
    const Float x = (c0 > 0 ? std::sqrt(x2) : c) * Float(kEntries - 1);
    const int i = std::min(int(x), kEntries - 2);
    const Float t = x - Float(i);
    return r[size_t(i)] * (1 - t) + r[size_t(i + 1)] * t;
  }
};

// The table for a film (thickness nm, index nf) on a substrate whose index at λ (nm) is
// `substrate(λ)` = (n, k).
std::shared_ptr<const ThinFilmRgbTable> make_thin_film_rgb_table(
    double thickness, double nf, const std::function<std::pair<double, double>(double)>& substrate);

// The film as carried by a model of colour U (Color or SampledSpectrum).
template <typename U>
struct ThinFilmT {
  Float thickness = 0;  // nm; 0: no film (the bare interface, exactly)
  Float eta = 1.5f;     // the film's index relative to the outside
  U lambda{};           // each channel's wavelength in nm: the path's (spectral), 650/550/450 (RGB)
  std::shared_ptr<const ThinFilmRgbTable> table;  // RGB mode's reflectance
  // The share of the surface the film covers (OpenPBR's thin_film_weight, SPEC-OPB
  // "Thin-film iridescence": "a blend between the BSDF with and without the presence of the
  // film"); the rest is the bare interface. reflectance() and mueller() are the blend,
  // film_reflectance() and film_mueller() the covered part alone.
  Float coverage = 1;

  bool active() const { return thickness > 0; }

  // R of the interface for light from the outside at cos1, over a substrate of relative
  // index n3 + i k3 per channel: (1 − coverage) of the bare interface's exact Fresnel
  // (fresnel.h) and coverage of the film's.
  U reflectance(Float cos1, const U& n3, const U& k3) const {
    const U r = film_reflectance(cos1, n3, k3);
    if (!(coverage < 1)) return r;
    const Float c = std::clamp(cos1, Float(0), Float(1));
    U bare;
    for (int j = 0; j < U::size(); ++j)
      bare[j] = k3[j] > 0 ? fresnel_conductor(c, n3[j], k3[j]) : fresnel_dielectric(c, n3[j]);
    return bare * (1 - coverage) + r * coverage;
  }
  U film_reflectance(Float cos1, const U& n3, const U& k3) const {
    if constexpr (std::is_same_v<U, Color>) {
      if (table) return table->lookup(cos1);
    }
    U out;
    for (int j = 0; j < U::size(); ++j)
      out[j] = Float(airy_film<double>(cos1, eta, thickness, n3[j], k3[j], lambda[j]).R());
    return out;
  }
  // The Mueller shape of the reflection (from inside a dielectric substrate when back) or
  // of the transmission, per channel at its wavelength; the bare part's is the Airy sum of
  // a film of thickness 0, which is the bare interface (r = (r12 + r23)/(1 + r12 r23) = r13).
  MuellerT<U> mueller(Float cos1, const U& n3, const U& k3, bool reflection, bool back) const {
    const MuellerT<U> m = film_mueller(cos1, n3, k3, reflection, back);
    if (!(coverage < 1)) return m;
    return shape(cos1, n3, k3, reflection, back, 0) * (1 - coverage) + m * coverage;
  }
  MuellerT<U> film_mueller(Float cos1, const U& n3, const U& k3, bool reflection, bool back) const {
    return shape(cos1, n3, k3, reflection, back, thickness);
  }

 private:
  MuellerT<U> shape(Float cos1, const U& n3, const U& k3, bool reflection, bool back, Float d) const {
    MuellerT<U> m;
    for (int j = 0; j < U::size(); ++j) {
      const auto a = airy_film<double>(cos1, eta, d, n3[j], k3[j], lambda[j], back);
      const MuellerT<double> one = reflection ? film_reflection_mueller(a) : film_transmission_mueller(a);
      for (int r = 0; r < 4; ++r)
        for (int c = 0; c < 4; ++c) m(r, c)[j] = Float(one(r, c));
    }
    return m;
  }
};

// RGB mode's wavelengths of the three channels (as an index's, spectrum_to_rgb.h).
inline Color thin_film_rgb_lambda() { return Color(kRgbIndexWavelengths[0], kRgbIndexWavelengths[1], kRgbIndexWavelengths[2]); }

// cos θ1 outside for light inside a dielectric substrate of relative index eta at
// |cos θ| = c; none (negative) beyond the critical angle (total internal reflection).
inline Float film_outside_cos(Float c, Float eta) {
  const Float s2 = eta * eta * std::max(Float(0), 1 - c * c);
  return s2 < 1 ? std::sqrt(1 - s2) : Float(-1);
}

// The outside cosine at which a film on a dielectric substrate of relative index eta is
// read, for light at |cos θ| = c inside or outside; negative where the bare substrate
// reflects totally (from inside beyond its critical angle, or from outside onto eta < 1
// beyond asin eta), where the lossless stack reflects everything: R = 1 exactly there
// (the table's interpolation across that kink, or its reduction of R = 1 to RGB, must
// not leak light into a direction Snell's law does not have).
inline Float film_read_cos(Float c, Float eta, bool inside) {
  c = std::min(c, Float(1));
  if (inside) return film_outside_cos(c, eta);
  return dielectric_cos2_t(c * c, 1 / eta) > 0 ? c : Float(-1);
}

}  // namespace gonio
