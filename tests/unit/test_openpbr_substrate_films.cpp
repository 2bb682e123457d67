// A thin film on openpbr's F82-tint metal and on its glass (SPEC-OPB "Thin-film
// iridescence"; issue 35): the effective complex index of an F82-tint curve
// (include/gonio/bxdf/f82_effective_index.h), the film's Airy sum over it, and the film's
// reflection and transmission on the glass, against this file's own arithmetic: the exact Fresnel
// of a complex index written with std::complex (Born & Wolf §13.4, the transmitted wave's
// n cos θ of non-negative imaginary part), Gulbrandsen's (2014) family written out and solved
// by plain bisection, and the film's two-interface Airy sum (Born & Wolf §1.6.4 eq. 57) with
// each interface's Fresnel amplitudes written here. The RGB table's reduction of the same
// film is checked by tests/reference/openpbr_reference.py's metal-film records.

#include <gtest/gtest.h>

#include <cmath>
#include <complex>

#include "gonio/bxdf/f82_effective_index.h"
#include "gonio/bxdf/openpbr.h"

namespace gonio {
namespace metal_film_test {

using Cx = std::complex<double>;

// n cos θ in the medium of complex index N for light from index 1 at cosine mu, the branch
// of the decaying (or outgoing) wave.
Cx n_cos(Cx N, double mu) {
  Cx w = std::sqrt(N * N - Cx(1 - mu * mu));
  if (w.imag() < 0) w = -w;
  return w;
}

// Unpolarized reflectance of the bare interface from index 1 onto N = n + ik.
double fresnel_exact(double mu, double n, double k) {
  const Cx N(n, k), w = n_cos(N, mu);
  const Cx rs = (mu - w) / (mu + w), rp = (N * N * mu - w) / (N * N * mu + w);
  return (std::norm(rs) + std::norm(rp)) / 2;
}

double schlick(double f0, double mu) { return f0 + (1 - f0) * std::pow(1 - mu, 5); }
double f82_curve(double f0, double tint, double mu) {
  const double mb = 1.0 / 7;
  const double a = schlick(f0, mb) * (1 - tint) / (mb * std::pow(1 - mb, 6));
  return std::clamp(schlick(f0, mu) - a * mu * std::pow(1 - mu, 6), 0.0, 1.0);
}

// Gulbrandsen 2014: n(g) between n_max (g = 0) and n_min (g = 1), k from r and n.
void member(double r, double g, double& n, double& k) {
  const double n_min = (1 - r) / (1 + r), n_max = (1 + std::sqrt(r)) / (1 - std::sqrt(r));
  n = g * n_min + (1 - g) * n_max;
  k = std::sqrt(std::max(0.0, (r * (n + 1) * (n + 1) - (n - 1) * (n - 1)) / (1 - r)));
}
double f_bar_of(double r, double g) {
  double n, k;
  member(r, g, n, k);
  return fresnel_exact(1.0 / 7, n, k);
}
// g with F(1/7) = tint × Schlick(1/7), by bisection (F(1/7) rises with g: MonotoneInG).
double solve_g(double r, double tint) {
  const double target = tint * schlick(r, 1.0 / 7);
  double lo = 0, hi = 1;
  if (f_bar_of(r, lo) >= target) return 0;
  if (f_bar_of(r, hi) <= target) return 1;
  for (int i = 0; i < 200; ++i) {
    const double mid = (lo + hi) / 2;
    (f_bar_of(r, mid) < target ? lo : hi) = mid;
  }
  return (lo + hi) / 2;
}

// The film (index nf, thickness d nm) on the substrate n + ik at wavelength lambda nm.
double airy(double mu, double nf, double d, double n, double k, double lambda) {
  const Cx N(n, k), w3 = n_cos(N, mu);
  const double cf = std::sqrt(1 - (1 - mu * mu) / (nf * nf)), wf = nf * cf;
  const Cx e = std::polar(1.0, 4 * kPiD * nf * d * cf / lambda);
  const auto sum = [&](Cx r12, Cx r23) { return std::norm((r12 + r23 * e) / (1.0 + r12 * r23 * e)); };
  const Cx rs12 = (mu - wf) / (mu + wf), rs23 = (wf - w3) / (wf + w3);
  const Cx rp12 = (nf * nf * mu - wf) / (nf * nf * mu + wf), rp23 = (N * N * wf - nf * nf * w3) / (N * N * wf + nf * nf * w3);
  return (sum(rs12, rs23) + sum(rp12, rp23)) / 2;
}

// A smooth openpbr of parameters p in spectral mode at wavelengths lambda, under a film of
// index nf and thickness d nm covering w.
OpenPbrBxDFT<SampledSpectrum> with_film(OpenPbrParams<SampledSpectrum> p, double w, double nf, double d,
                                        const SampledSpectrum& lambda) {
  p.specular_roughness = 0;
  p.thin_film_weight = Float(w);
  p.thin_film_thickness = Float(d / 1000);
  p.thin_film_ior = Float(nf);
  ThinFilmT<SampledSpectrum> film;
  film.thickness = Float(d);
  film.eta = Float(nf);
  film.lambda = lambda;
  return OpenPbrBxDFT<SampledSpectrum>::make(p, film);
}

TEST(F82EffectiveIndex, MonotoneInG) {
  for (double r : {0.02, 0.05, 0.2, 0.5, 0.8, 0.95, 0.99}) {
    double prev = -1;
    for (int i = 0; i <= 200; ++i) {
      const double f = f_bar_of(r, i / 200.0);
      EXPECT_GT(f, prev) << "r " << r << " g " << i / 200.0;
      prev = f;
    }
  }
}

// Both values that define the F82 curve are matched by the exact Fresnel of the index, which
// lies on Gulbrandsen's family.
TEST(F82EffectiveIndex, MatchesF0AndTheTintAtOneSeventh) {
  for (double r : {0.02, 0.2, 0.5, 0.8, 0.95})
    for (double tint : {0.7, 0.9, 1.0}) {
      if (f_bar_of(r, 0) > tint * schlick(r, 1.0 / 7)) continue;  // out of reach: OutOfReachTakesTheEnd
      const ComplexIndex c = f82_effective_index(r, tint);
      EXPECT_NEAR(fresnel_exact(1, c.n, c.k), r, 1e-9) << r << " " << tint;
      EXPECT_NEAR(fresnel_exact(1.0 / 7, c.n, c.k), f82_curve(r, tint, 1.0 / 7), 1e-8) << r << " " << tint;
      double n, k;
      member(r, solve_g(r, tint), n, k);
      EXPECT_NEAR(c.n, n, 1e-6 * n) << r << " " << tint;
      EXPECT_NEAR(c.k, k, 1e-6 * std::max(k, 1.0)) << r << " " << tint;
    }
}

TEST(F82EffectiveIndex, OutOfReachTakesTheEnd) {
  // r = 0.8: the dielectric end reflects 0.651 of Schlick at 1/7, so a tint of 0.3 takes it.
  const ComplexIndex c = f82_effective_index(0.8, 0.3);
  const double n_max = (1 + std::sqrt(0.8)) / (1 - std::sqrt(0.8));
  EXPECT_NEAR(c.n, n_max, 1e-9 * n_max);
  EXPECT_NEAR(c.k, 0, 1e-5);  // k(n_max) = 0 up to the rounding of r (n + 1)² − (n − 1)²
  // Nothing reflected at normal incidence: the ambient index.
  const ComplexIndex none = f82_effective_index(0, 0.5);
  EXPECT_EQ(none.n, 1);
  EXPECT_EQ(none.k, 0);
  for (double f0 : {1.0, 0.99999, std::nan("")})
    for (double t : {0.0, 1.0, std::nan("")}) {
      const ComplexIndex e = f82_effective_index(f0, t);
      EXPECT_TRUE(std::isfinite(e.n) && std::isfinite(e.k) && e.n > 0 && e.k >= 0) << f0 << " " << t;
    }
}

// The smooth metal's mirror weight in spectral mode: (1 − w) F82(μ) + w Airy(μ) at each
// wavelength of the path, over the effective index of the (grey) F82 curve.
TEST(OpenPbrMetalFilm, MirrorIsTheAirySumOverTheEffectiveIndex) {
  using SS = SampledSpectrum;
  const double f0 = 0.7, tint = 0.85, nf = 1.5, d = 400;
  double n, k;
  member(f0, solve_g(f0, tint), n, k);
  const SS lambda(450.0f, 520.0f, 610.0f, 680.0f);
  for (double w : {1.0, 0.6}) {
    OpenPbrParams<SS> p;
    p.base_metalness = 1;
    p.base_color = SS(Float(f0));
    p.specular_color = SS(Float(tint));
    const auto m = with_film(p, w, nf, d, lambda);
    for (double th : {0.0, 30.0, 60.0, 80.0, 89.0}) {
      const double mu = std::cos(th * kPiD / 180);
      const Vec3 wo{Float(std::sqrt(1 - mu * mu)), 0, Float(mu)};
      const auto s = m.sample(wo, 0.5f, 0.5f, 0.5f);
      ASSERT_TRUE(s && s->delta) << th;
      for (int j = 0; j < SS::size(); ++j) {
        const double want = (1 - w) * f82_curve(f0, tint, mu) + w * airy(mu, nf, d, n, k, lambda[j]);
        EXPECT_NEAR(s->weight[j], want, 2e-5) << "theta " << th << " lambda " << lambda[j] << " weight " << w;
      }
    }
  }
}

// The smooth glass (transmission_weight 1) in spectral mode: its delta reflection is
// (1 − w) F(μ) + w Airy(μ) over the glass's index at each wavelength, and (importance mode:
// the fraction of light arriving along wo) its delta transmission the rest, from outside
// and, at the corresponding angle, from inside (the film's R is the same from both sides).
TEST(OpenPbrGlassFilm, SmoothGlassReflectsTheAirySumAndTransmitsTheRest) {
  using SS = SampledSpectrum;
  const double eta = 1.5, nf = 1.33, d = 350;
  const SS lambda(440.0f, 530.0f, 600.0f, 690.0f);
  for (double w : {1.0, 0.5}) {
    OpenPbrParams<SS> p;
    p.transmission_weight = 1;
    p.specular_ior = Float(eta);
    const auto m = with_film(p, w, nf, d, lambda);
    for (double th : {0.0, 35.0, 70.0, 85.0})
      for (bool inside : {false, true}) {
        const double mu = std::cos(th * kPiD / 180);  // outside
        const double mu_in = std::sqrt(1 - (1 - mu * mu) / (eta * eta));
        const double c = inside ? mu_in : mu;
        const Vec3 wo{Float(std::sqrt(1 - c * c)), 0, Float(inside ? -c : c)};
        double r[4] = {0, 0, 0, 0}, t[4] = {0, 0, 0, 0};
        const int n = 4000;
        for (int i = 0; i < n; ++i) {
          const auto s = m.sample(wo, Float((i + 0.5) / n), 0.5f, 0.5f, TransportMode::Importance);
          if (!s) continue;
          ASSERT_TRUE(s->delta);
          for (int j = 0; j < 4; ++j) ((s->wi.z > 0) == (wo.z > 0) ? r : t)[j] += s->weight[j] / n;
        }
        for (int j = 0; j < 4; ++j) {
          const double want = (1 - w) * fresnel_exact(mu, eta, 0) + w * airy(mu, nf, d, eta, 0, lambda[j]);
          EXPECT_NEAR(r[j], want, 2e-4) << "theta " << th << (inside ? " inside" : "") << " lambda " << lambda[j] << " w " << w;
          EXPECT_NEAR(t[j], 1 - want, 2e-4) << "theta " << th << (inside ? " inside" : "") << " lambda " << lambda[j] << " w " << w;
        }
      }
  }
}

}  // namespace metal_film_test
}  // namespace gonio
