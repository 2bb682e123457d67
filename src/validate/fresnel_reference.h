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

// Reflectance of a single film (index nf, thickness d) on a substrate of complex index
// n3 + i k3, for light from a medium of index 1 at cos θ1 = c, wavelength lambda (same unit
// as d): Born & Wolf's characteristic matrix of a homogeneous layer (Principles of
// Optics, §1.6.2, eqs. 1.6(34) and 1.6(56a)), a different formalism from the Airy sum of
// the code under test. For each polarization with p_j = n_j cos θ_j (TE) or cos θ_j / n_j
// (TM), β = (2π/λ) nf d cos θ_f and M = [[cos β, −i sin β / p_f], [−i p_f sin β, cos β]]:
//   r = ((m11 + m12 p_3) p_1 − (m21 + m22 p_3)) / ((m11 + m12 p_3) p_1 + (m21 + m22 p_3)).
// The substrate's n cos θ = √(N² − sin²θ1), the root with Im ≥ 0 (a decaying wave).
inline double reference_film_reflectance(double c, double nf, double d, double n3, double k3, double lambda) {
  using cx = std::complex<double>;
  c = std::min(std::abs(c), 1.0);
  if (c == 0) return 1;  // grazing: every amplitude tends to −1
  const double s2 = 1 - c * c;
  const double cf = std::sqrt(std::max(0.0, 1 - s2 / (nf * nf)));
  const cx N(n3, k3), N2 = N * N;
  cx w3 = std::sqrt(N2 - s2);  // N cos θ3
  if (w3.imag() < 0) w3 = -w3;
  const double beta = 2 * 3.14159265358979323846 / lambda * nf * d * cf;
  const cx i(0, 1);
  double R = 0;
  for (int pol = 0; pol < 2; ++pol) {
    const cx p1 = pol == 0 ? cx(c) : cx(c);                      // n1 = 1
    const cx pf = pol == 0 ? cx(nf * cf) : cx(cf / nf);
    const cx p3 = pol == 0 ? w3 : w3 / N2;                       // cos θ3 / N = N cos θ3 / N²
    const cx m11 = std::cos(beta), m22 = std::cos(beta);
    const cx m12 = -i * std::sin(beta) / pf, m21 = -i * pf * std::sin(beta);
    const cx a = (m11 + m12 * p3) * p1, b = m21 + m22 * p3;
    const cx r = (a + b) == cx(0) ? cx(1) : (a - b) / (a + b);
    R += std::min(1.0, std::norm(r)) / 2;
  }
  return R;
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

// F82-tint (Hoffman 2023; SPEC §2): Schlick's curve S minus a μ (1 − μ)⁶, the one
// coefficient a fixed by the condition F(μ̄) = f82 S(μ̄) at μ̄ = 1/7, i.e.
// a = (S(μ̄) − f82 S(μ̄)) / (μ̄ (1 − μ̄)⁶) (here with std::pow), and F clamped to [0, 1].
inline double reference_fresnel_f82(double c, double f0, double f82) {
  const double mu = std::min(std::abs(c), 1.0), mu_bar = 1.0 / 7.0;
  const double s_bar = reference_fresnel_schlick(mu_bar, f0);
  const double a = (s_bar - f82 * s_bar) / (mu_bar * std::pow(1 - mu_bar, 6));
  return std::clamp(reference_fresnel_schlick(mu, f0) - a * mu * std::pow(1 - mu, 6), 0.0, 1.0);
}

}  // namespace gonio::validation
