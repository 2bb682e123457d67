#pragma once
// The validator's own Fresnel reflectances: a test oracle for the delta lobes, written
// apart from include/gonio/fresnel.h (the code the validator checks) and in a different
// form — angles and Snell's law in double precision for dielectrics, complex arithmetic
// for conductors — so that a slip in the library's formulas cannot hide behind itself.

#include <algorithm>
#include <cmath>
#include <complex>

namespace gonio::validation {

// Unpolarised reflectance of a smooth interface between two dielectrics, for light
// meeting it at cos θi = c (0 < c ≤ 1) from the medium of index n1, with e = n2 / n1.
// Snell's law: sin θt = sin θi / e; total reflection when sin θt ≥ 1 (SPEC §1).
// Fresnel's sine and tangent laws (Hecht, Optics, §4.6.2, eqs. 4.42 and 4.43):
//   r⊥ = −sin(θi − θt) / sin(θi + θt),   r∥ = tan(θi − θt) / tan(θi + θt),
// R = (r⊥² + r∥²) / 2. At normal incidence both are 0/0; their limit is
// ((e − 1)/(e + 1))² (Hecht eq. 4.47), which the sine law meets to O(θi²).
inline double reference_fresnel_dielectric(double c, double e) {
  c = std::min(std::abs(c), 1.0);
  const double sin_i = std::sqrt(std::max(0.0, 1 - c * c));
  const double sin_t = sin_i / e;
  if (sin_t >= 1) return 1;  // total internal reflection
  const double ti = std::atan2(sin_i, c), tt = std::asin(sin_t);
  if (ti < 1e-7) {
    const double r = (e - 1) / (e + 1);
    return r * r;
  }
  if (c == 0) return 1;  // grazing: both amplitudes tend to −1 and 1
  const double rs = std::sin(ti - tt) / std::sin(ti + tt);
  const double rp = std::tan(ti - tt) / std::tan(ti + tt);
  return std::min(1.0, (rs * rs + rp * rp) / 2);
}

// The two polarizations' reflectances R⊥ = r⊥², R∥ = r∥² of the same interface (the laws
// above; at normal incidence both are ((e − 1)/(e + 1))², under total reflection both 1).
inline void reference_fresnel_dielectric_sp(double c, double e, double& rs2, double& rp2) {
  c = std::min(std::abs(c), 1.0);
  const double sin_i = std::sqrt(std::max(0.0, 1 - c * c));
  const double sin_t = sin_i / e;
  rs2 = rp2 = 1;
  if (sin_t >= 1 || c == 0) return;
  const double ti = std::atan2(sin_i, c), tt = std::asin(sin_t);
  if (ti < 1e-7) {
    rs2 = rp2 = ((e - 1) / (e + 1)) * ((e - 1) / (e + 1));
    return;
  }
  const double rs = std::sin(ti - tt) / std::sin(ti + tt), rp = std::tan(ti - tt) / std::tan(ti + tt);
  rs2 = std::min(1.0, rs * rs);
  rp2 = std::min(1.0, rp * rp);
}

// A thin sheet of relative index e (the same medium on both sides), its faces and all
// internal reflections summed incoherently per polarization: the geometric series
// r + (1 − r)² r Σ r^(2k) = 2r / (1 + r) for each, averaged (Born & Wolf §1.6, a plate's
// multiple reflections without interference). Its transmittance is 1 minus this.
inline double reference_thin_sheet(double c, double e) {
  double rs2 = 1, rp2 = 1;
  reference_fresnel_dielectric_sp(c, e, rs2, rp2);
  return (2 * rs2 / (1 + rs2) + 2 * rp2 / (1 + rp2)) / 2;
}

// Unpolarised reflectance of a conductor of complex relative index n = η + iκ at
// cos θi = c, from Snell's law with a complex refraction angle (Born & Wolf, Principles
// of Optics, §14.2): n cos θt = w = √(n² − sin²θi), the root with Re w ≥ 0 (the wave
// that decays into the metal), and the Fresnel amplitudes
//   r⊥ = (cos θi − w) / (cos θi + w),   r∥ = (n² cos θi − w) / (n² cos θi + w).
inline double reference_fresnel_conductor(double c, double eta, double kappa) {
  c = std::min(std::abs(c), 1.0);
  if (c == 0) return 1;
  const std::complex<double> n(eta, kappa), n2 = n * n;
  const std::complex<double> w = std::sqrt(n2 - (1 - c * c));  // principal root: Re ≥ 0
  const std::complex<double> rs = (c - w) / (c + w), rp = (n2 * c - w) / (n2 * c + w);
  return std::min(1.0, (std::norm(rs) + std::norm(rp)) / 2);
}

// Schlick's approximation (Schlick 1994, eq. 24): F0 + (1 − F0)(1 − cos θ)⁵.
inline double reference_fresnel_schlick(double c, double f0) {
  const double m = 1 - std::min(std::abs(c), 1.0);
  return f0 + (1 - f0) * m * m * m * m * m;
}

}  // namespace gonio::validation
