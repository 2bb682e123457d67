// Issue 13 item 5: the single-bounce component of a Gaussian microsurface with white
// mirror facets (F = 1) against the single-scattering Smith microfacet model for
// Beckmann, α = 0.3, away from grazing — the part where theory is exact up to Smith's
// masking assumption.
//
// The model (smith_beckmann_model.h) is written again from the papers, not taken from
// gonio's roughconductor.
// The measured surface is a height field — one surface whose heights shadow and mask
// both directions at once — so the height-correlated form is its model; the separable one
// counts a facet shadowed and masked as if by two independent surfaces. At α = 0.3 the
// two differ by < 0.1% below 65°; at α = 1 the separable form's single-bounce albedo is
// 1–3% lower and further from the measurement (HeightCorrelatedNotSeparableAt1 below).
// The height-correlated form is the one held to 3%.
//
// The first bounce: a Microsurface with max_bounces = 1 drops (Fate::Capped) every ray that
// meets a second facet, so exactly the rays that leave after one facet reach the
// detectors and the albedo.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <vector>

#include "../test_common.h"
#include "../unit/test_scale.h"
#include "gonio/material.h"
#include "gonio/math/constants.h"
#include "gonio/measure/gantry.h"
#include "gonio/measure/gaussian_surface.h"
#include "smith_beckmann_model.h"

namespace gonio::measure {
namespace {

using namespace smith_beckmann;

// Single-scattering albedo ∫ f cos θo dωo by the midpoint rule on (θo, φo); the lobe
// (width ~α) spans hundreds of cells, and the result is symmetric in φo.
double model_albedo(double theta_i, double alpha, Masking g) {
  const V i = dir(theta_i, 0);
  const int nt = 720, np = 360;
  const double dt = kPiD / 2 / nt, dp = kPiD / np;
  double sum = 0;
  for (int a = 0; a < nt; ++a) {
    const double t = (a + 0.5) * dt;
    for (int b = 0; b < np; ++b) {
      const V o = dir(t, (b + 0.5) * dp);
      sum += model_f(i, o, alpha, g) * o.z * std::sin(t);
    }
  }
  return 2 * sum * dt * dp;
}

// What a detector cone of half-angle β around (θc, φc) reads: ∫_cone f cos θ dω /
// ∫_cone cos θ dω (gantry.h), by the midpoint rule in the cone's own polar angles.
double model_detector(double theta_i, double theta_c, double phi_c, double beta, double alpha, Masking g) {
  const V i = dir(theta_i, 0);
  const V c = dir(theta_c, phi_c);
  // An orthonormal frame (c, u, w) around the axis.
  const V u{std::cos(theta_c) * std::cos(phi_c), std::cos(theta_c) * std::sin(phi_c), -std::sin(theta_c)};
  const V w{-std::sin(phi_c), std::cos(phi_c), 0};
  const int nr = 120, np = 240;
  double num = 0, den = 0;
  for (int a = 0; a < nr; ++a) {
    const double r = (a + 0.5) * beta / nr, sr = std::sin(r), cr = std::cos(r);
    for (int b = 0; b < np; ++b) {
      const double p = (b + 0.5) * 2 * kPiD / np;
      const double cu = sr * std::cos(p), cw = sr * std::sin(p);
      const V o{cr * c.x + cu * u.x + cw * w.x, cr * c.y + cu * u.y + cw * w.y, cr * c.z + cu * u.z + cw * w.z};
      if (o.z <= 0) continue;
      num += model_f(i, o, alpha, g) * o.z * sr;
      den += o.z * sr;
    }
  }
  return num / den;
}

// The first bounce of a Gaussian surface of roughness alpha, measured by the gantry at
// `theta_i` with detectors (half-angle 10°) in the plane of incidence on the specular side.
// A finite patch holds a finite number of facets in a detector's cone of half vectors, so
// its readings scatter from realisation to realisation: on a 256² patch with the default
// correlation (8 cells, 32 × 32 correlation lengths) the lobe's peak moved by up to 4%
// between seeds, far beyond the rays' noise. Here n = 512 and a correlation of 4 cells
// (128 × 128 lengths): the peak moved by < 1% between two seeds, and the first-bounce
// albedo at α = 1 by < 1% between correlations of 4, 8 and 16 cells (the triangulation
// is fine enough). The gantry is also turned to `azimuths` azimuths φ (detectors with it) and the readings
// averaged: each azimuth sees other facets of the same patch.
struct Pooled {
  double theta_i = 0, albedo = 0, stderr_albedo = 0;
  std::vector<double> theta_o, f, stderr_f;
};
std::vector<Pooled> measure_first_bounce(double alpha, const std::vector<double>& theta_i,
                                         const std::vector<double>& theta_o, int azimuths, std::uint64_t rays) {
  GaussianSurfaceParams p;
  p.alpha_x = p.alpha_y = alpha;
  p.resolution = 512;
  p.correlation = 4.0 / p.resolution;
  p.seed = 7;
  const Microsurface surface(gaussian_height_field(p), parse_material(R"({"type":"mirror","reflectance":1})"), 1);
  std::vector<Pooled> out(theta_i.size());
  for (std::size_t t = 0; t < theta_i.size(); ++t) {
    out[t].theta_i = theta_i[t];
    out[t].theta_o = theta_o;
    out[t].f.assign(theta_o.size(), 0);
    out[t].stderr_f.assign(theta_o.size(), 0);
  }
  std::vector<std::vector<double>> var_f(theta_i.size(), std::vector<double>(theta_o.size(), 0));
  std::vector<double> var_a(theta_i.size(), 0);
  for (int k = 0; k < azimuths; ++k) {
    const double phi = 360.0 * k / azimuths;
    GantrySpec spec;
    spec.theta_i = theta_i;
    spec.phi_i = {phi};
    spec.theta_o = theta_o;
    spec.phi_o = {phi + 180};
    spec.aperture = 10;
    RunOptions o;
    o.samples = rays * theta_i.size();
    o.seed = 3 + std::uint64_t(k);
    const GantryReading r = run_gantry(surface, spec, o);
    for (std::size_t t = 0; t < theta_i.size(); ++t) {
      const IncidenceReading& inc = r.incidences[t];
      out[t].albedo += inc.albedo[0] / azimuths;
      var_a[t] += std::pow(inc.stderr_albedo[0] / azimuths, 2);
      for (std::size_t d = 0; d < theta_o.size(); ++d) {
        out[t].f[d] += inc.detectors[d].f[0] / azimuths;
        var_f[t][d] += std::pow(inc.detectors[d].stderr_f[0] / azimuths, 2);
      }
    }
  }
  for (std::size_t t = 0; t < theta_i.size(); ++t) {
    out[t].stderr_albedo = std::sqrt(var_a[t]);
    for (std::size_t d = 0; d < theta_o.size(); ++d) out[t].stderr_f[d] = std::sqrt(var_f[t][d]);
  }
  return out;
}

constexpr double kAperture = 10 * kDeg;

const std::vector<Pooled>& alpha03() {
  static const std::vector<Pooled> m =
      measure_first_bounce(0.3, {0, 30, 50, 65}, {10, 30, 50, 65}, 4, gonio::test::scaled(100000, 50000));
  return m;
}

// The first bounce at α = 0.3 (one test: ctest runs each test in its own process, and
// each would measure again). The albedo, all power that left after one facet, integrates
// over every facet the light sees, so the realisation's scatter averages out. The
// detectors are in the plane of incidence on the specular side; those where the lobe is
// (|tan θh| ≤ α: D at least e^−1 of its peak) are held to 3%; further out the rays'
// standard error grows past the 1.2% that keeps 3% meaningful.
TEST(TheorySingleBounce, FirstBounceMatchesSmithBeckmannAt03) {
  for (const Pooled& m : alpha03()) {
    const double ti = m.theta_i * kDeg;
    const double corr = model_albedo(ti, 0.3, Masking::HeightCorrelated);
    const double sep = model_albedo(ti, 0.3, Masking::Separable);
    std::printf("α 0.3 albedo θi=%4.0f measured %.4f ± %.4f  height-correlated %.4f (%+.2f%%)  separable %.4f (%+.2f%%)\n",
                m.theta_i, m.albedo, m.stderr_albedo, corr, 100 * (m.albedo / corr - 1), sep,
                100 * (m.albedo / sep - 1));
    EXPECT_LT(m.stderr_albedo, 0.005 * corr) << "θi " << m.theta_i << ": too noisy to test 3%";
    EXPECT_NEAR(m.albedo / corr, 1, 0.03) << "θi " << m.theta_i;
  }
  int tested = 0;
  for (const Pooled& m : alpha03()) {
    for (std::size_t d = 0; d < m.theta_o.size(); ++d) {
      const double ti = m.theta_i * kDeg, to = m.theta_o[d] * kDeg;
      const double model = model_detector(ti, to, kPiD, kAperture, 0.3, Masking::HeightCorrelated);
      const double sep = model_detector(ti, to, kPiD, kAperture, 0.3, Masking::Separable);
      const double th = std::abs(ti - to) / 2;
      std::printf("α 0.3 θi=%3.0f θo=%3.0f  f %.4f ± %.4f  height-correlated %.4f (%+.2f%%)  separable %.4f (%+.2f%%)%s\n",
                  m.theta_i, m.theta_o[d], m.f[d], m.stderr_f[d], model, 100 * (m.f[d] / model - 1), sep,
                  100 * (m.f[d] / sep - 1), std::tan(th) <= 0.3 ? "" : "  (tail, not tested)");
      if (std::tan(th) > 0.3) continue;
      ++tested;
      // 3% must stay several standard errors wide (≥ 5 in Release, ≥ 2.5 at GONIO_TEST_SCALE 0.1).
      EXPECT_LT(m.stderr_f[d], 0.012 * model) << "θi " << m.theta_i << " θo " << m.theta_o[d];
      EXPECT_NEAR(m.f[d] / model, 1, 0.03) << "θi " << m.theta_i << " θo " << m.theta_o[d];
    }
  }
  EXPECT_GE(tested, 8);
}

// Which Smith form: at α = 0.3 the two agree to 0.1% below 65° (Λ ≪ 1, so the product
// Λ(i)Λ(o) that tells them apart is negligible). At α = 1 Λ is large and they part:
// the measured first bounce decides.
TEST(TheorySingleBounce, HeightCorrelatedNotSeparableAt1) {
  const std::vector<Pooled> m = measure_first_bounce(1.0, {0, 40, 60, 70}, {}, 1, gonio::test::scaled(100000, 50000));
  for (const Pooled& r : m) {
    const double ti = r.theta_i * kDeg;
    const double corr = model_albedo(ti, 1.0, Masking::HeightCorrelated);
    const double sep = model_albedo(ti, 1.0, Masking::Separable);
    std::printf("α 1.0 albedo θi=%4.0f measured %.4f ± %.4f  height-correlated %.4f (%+.2f%%)  separable %.4f (%+.2f%%)\n",
                r.theta_i, r.albedo, r.stderr_albedo, corr, 100 * (r.albedo / corr - 1), sep, 100 * (r.albedo / sep - 1));
    // Even the height-correlated form is a few percent below the measurement at α = 1
    // (2–4% at 40–70°, the same for correlations of 4, 8 and 16 cells): Smith's
    // assumption that heights and slopes are uncorrelated along a ray is not exact for a
    // Gaussian surface this rough. The bound is that documented disagreement.
    EXPECT_NEAR(r.albedo / corr, 1, 0.05) << "θi " << r.theta_i;
    if (r.theta_i < 60) continue;
    // Where the forms part by many standard errors, the height-correlated one is closer.
    EXPECT_GT(corr - sep, 5 * r.stderr_albedo) << "θi " << r.theta_i;
    EXPECT_LT(std::abs(r.albedo - corr), std::abs(r.albedo - sep)) << "θi " << r.theta_i;
  }
}

}  // namespace
}  // namespace gonio::measure
