// The sheen lobe (bxdf/sheen.h; Zeltner, Burley & Chiang 2022) against values computed
// here, independently of the model: the LTC density from the matrix M⁻¹ and the Jacobian
// of Heitz et al. 2016 (not the model's simplified a² z / (π |w′|⁴)), its normalisation
// and the lobe's albedo by quadrature over the sphere, the published fit of R typed in
// again, the build-time table of E_avg against Simpson's rule here, energy ≤ 1 over the
// whole parameter range, finite values at the extremes of roughness, and the measured
// reciprocity error that docs/testing.md publishes.

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <vector>

#include "gonio/bxdf.h"
#include "gonio/material.h"
#include "gonio/reflectance.h"
#include "gonio/math/spherical.h"
#include "gonio/rng.h"
#include "gonio/validate.h"

namespace gonio {
namespace sheen_test {

// R(μ, r) of the paper's fit as published by MaterialX 1.39 (mx_microfacet_sheen.glsl,
// zeltner_sheen_dir_albedo), typed in again in double; r clamped to [0.01, 1], R ≥ 0.
double published_R(double mu, double r) {
  r = std::clamp(r, 0.01, 1.0);
  const double s = r * (0.0206607 + 1.58491 * r) / (0.0379424 + r * (1.32227 + r));
  const double m = r * (-0.193854 + r * (-1.14885 + r * (1.7932 - 0.95943 * r * r))) / (0.046391 + r);
  const double o = r * (0.000654023 + (-0.0207818 + 0.119681 * r) * r) / (1.26264 + r * (-1.92021 + r));
  return std::max(0.0, std::exp(-0.5 * (mu - m) * (mu - m) / (s * s)) / (s * std::sqrt(2 * kPiD)) + o);
}
void published_ab(double mu, double r, double& a, double& b) {
  r = std::clamp(r, 0.01, 1.0);
  a = (2.58126 * mu + 0.813703 * r) * r / (1.0 + 0.310327 * mu * mu + 2.60994 * mu * r);
  b = std::sqrt(1.0 - mu) * (r - 1.0) * r * r * r / (0.0000254053 + 1.71228 * mu - 1.71506 * mu * r + 1.34174 * r * r);
}

// The LTC density by its definition (Heitz et al. 2016, eq. 1): D(w) = D_cos(w′/|w′|)
// |det M⁻¹| / |w′|³, w′ = M⁻¹ w, with the 3 × 3 matrix multiplied out in the frame of wo.
double ltc_density(const Vec3& wo, const Vec3& wi, double r) {
  double a, b;
  published_ab(std::min(double(wo.z), 1.0), r, a, b);
  const double t = std::hypot(double(wo.x), double(wo.y));
  const double ex[3] = {t > 0 ? wo.x / t : 1.0, t > 0 ? wo.y / t : 0.0, 0};
  const double ey[3] = {-ex[1], ex[0], 0};
  const double w[3] = {wi.x * ex[0] + wi.y * ex[1], wi.x * ey[0] + wi.y * ey[1], double(wi.z)};
  const double minv[3][3] = {{a, 0, b}, {0, a, 0}, {0, 0, 1}};
  double v[3] = {};
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) v[i] += minv[i][j] * w[j];
  const double n = std::sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
  const double det = minv[0][0] * (minv[1][1] * minv[2][2] - minv[1][2] * minv[2][1]) -
                     minv[0][1] * (minv[1][0] * minv[2][2] - minv[1][2] * minv[2][0]) +
                     minv[0][2] * (minv[1][0] * minv[2][1] - minv[1][1] * minv[2][0]);
  return std::max(0.0, v[2] / n) / kPiD * std::abs(det) / (n * n * n);
}

Vec3 at(double mu, double phi) {
  const double s = std::sqrt(std::max(0.0, 1 - mu * mu));
  return {Float(s * std::cos(phi)), Float(s * std::sin(phi)), Float(mu)};
}

// ∫ g(w) dω over the sphere by the midpoint rule in (θ, φ), n × 2n cells; the lobe's
// width ≥ 0.02 rad for the roughness used with it (≥ 0.1), so 1000 × 2000 cells resolve it.
template <typename G>
double sphere_integral(G&& g, int n = 1000) {
  double sum = 0;
  const double dt = kPiD / n, dp = kPiD / n;
  for (int i = 0; i < n; ++i) {
    const double th = (i + 0.5) * dt, st = std::sin(th), ct = std::cos(th);
    for (int j = 0; j < 2 * n; ++j) {
      const double ph = (j + 0.5) * dp;
      sum += g(Vec3{Float(st * std::cos(ph)), Float(st * std::sin(ph)), Float(ct)}) * st * dt * dp;
    }
  }
  return sum;
}

SheenBxDF sheen(double r, Color c = Color(1.0f)) {
  SheenBxDF m;
  m.color = c;
  m.roughness = Float(r);
  return m;
}

TEST(Sheen, DensityIsTheLinearlyTransformedCosine) {
  Pcg32 rng(7);
  for (double r : {0.001, 0.01, 0.05, 0.2, 0.5, 0.8, 1.0})
    for (int k = 0; k < 400; ++k) {
      const Vec3 wo = at(0.01 + 0.99 * rng.next_float(), 6.283 * rng.next_float());
      const Vec3 wi = at(0.01 + 0.99 * rng.next_float(), 6.283 * rng.next_float());
      const double want = ltc_density(wo, wi, r);
      EXPECT_NEAR(sheen(r).pdf(wo, wi), want, 2e-5 * want + 1e-12) << "r " << r;
      // f = color R(μo) D(wi) / μi, with R of the published fit.
      const double f = published_R(std::min(double(wo.z), 1.0), r) * want / wi.z;
      EXPECT_NEAR(sheen(r, Color(0.5f, 1.0f, 0.25f)).f(wo, wi)[1], f, 2e-5 * f + 1e-12) << "r " << r;
      EXPECT_NEAR(sheen(r, Color(0.5f, 1.0f, 0.25f)).f(wo, wi)[2], 0.25 * f, 2e-5 * f + 1e-12) << "r " << r;
    }
}

// The fused eval (one LTC; what the renderer calls, and what openpbr's fuzz calls with the
// albedo it already has) against the same published forms, both modes, both sides:
// radiance f = color R(μo) D_wo(wi)/μi, pdf D_wo(wi); importance f = color R(μi) D_wi(wo)/μo,
// pdf ½ (D_wo(wi) + μi/π).
TEST(Sheen, FusedEvalIsTheLtcInBothModes) {
  Pcg32 rng(11);
  const Color tint(0.5f, 1.0f, 0.25f);
  for (double r : {0.01, 0.2, 0.5, 1.0})
    for (int k = 0; k < 300; ++k) {
      Vec3 wo = at(0.01 + 0.99 * rng.next_float(), 6.283 * rng.next_float());
      Vec3 wi = at(0.01 + 0.99 * rng.next_float(), 6.283 * rng.next_float());
      const double d_o = ltc_density(wo, wi, r), d_i = ltc_density(wi, wo, r);
      const double f_rad = published_R(std::min(double(wo.z), 1.0), r) * d_o / wi.z;
      const double f_imp = published_R(std::min(double(wi.z), 1.0), r) * d_i / wo.z;
      const double p_imp = 0.5 * (d_o + wi.z / kPiD);
      if (k % 2) {  // the lower side: the same values mirrored
        wo.z = -wo.z;
        wi.z = -wi.z;
      }
      const BSDFEval e = sheen(r, tint).eval(wo, wi);
      EXPECT_NEAR(e.f[1], f_rad, 2e-5 * f_rad + 1e-12) << "r " << r;
      EXPECT_NEAR(e.f[2], 0.25 * f_rad, 2e-5 * f_rad + 1e-12) << "r " << r;
      EXPECT_NEAR(e.pdf, d_o, 2e-5 * d_o + 1e-12) << "r " << r;
      const BSDFEval ei = sheen(r, tint).eval(wo, wi, TransportMode::Importance);
      EXPECT_NEAR(ei.f[0], 0.5 * f_imp, 2e-5 * f_imp + 1e-12) << "r " << r;
      EXPECT_NEAR(ei.pdf, p_imp, 2e-5 * p_imp + 1e-12) << "r " << r;
      // A given albedo R(μo) is the one used (openpbr passes its layer's).
      const Vec3 wo_u{wo.x, wo.y, std::abs(wo.z)}, wi_u{wi.x, wi.y, std::abs(wi.z)};
      EXPECT_NEAR(sheen(r, tint).eval_upper(wo_u, wi_u, TransportMode::Radiance, Float(0.5)).f[1], 0.5 * d_o / wi_u.z,
                  2e-5 * d_o / wi_u.z + 1e-12);
    }
}

TEST(Sheen, LtcIntegratesToOneAboveTheHorizon) {
  for (double r : {0.1, 0.3, 0.5, 1.0})
    for (double mu : {1.0, 0.7, 0.3, 0.05}) {
      const Vec3 wo = at(mu, 0.4);
      const SheenBxDF m = sheen(r);
      double below = 0;
      const double total = sphere_integral([&](const Vec3& w) {
        const double d = ltc_density(wo, w, r);
        if (w.z < 0) below += d;
        return d;
      });
      EXPECT_NEAR(total, 1.0, 2e-3) << "r " << r << ", mu " << mu;
      EXPECT_EQ(below, 0.0);
      // The model's own pdf integrates to 1 as well (what sample() draws from).
      EXPECT_NEAR(sphere_integral([&](const Vec3& w) { return double(m.pdf(wo, w)); }), 1.0, 2e-3)
          << "r " << r << ", mu " << mu;
    }
}

// The lobe loses nothing below the horizon, so its directional albedo (radiance mode) is
// the paper's R itself; the model's albedo() says so too.
TEST(Sheen, DirectionalAlbedoIsThePapersR) {
  for (double r : {0.1, 0.25, 0.5, 0.75, 1.0})
    for (double mu : {1.0, 0.8, 0.5, 0.2, 0.05}) {
      const Vec3 wo = at(mu, 1.1);
      const SheenBxDF m = sheen(r, Color(1.0f, 0.5f, 0.2f));
      const double e = sphere_integral([&](const Vec3& w) { return double(m.f(wo, w)[0]) * std::max(0.0f, w.z); });
      const double want = published_R(mu, r);
      EXPECT_NEAR(e, want, 2e-3 * want + 1e-6) << "r " << r << ", mu " << mu;
      const auto a = m.albedo(wo, TransportMode::Radiance);
      ASSERT_TRUE(a);
      EXPECT_NEAR(a->reflectance[0], want, 1e-5 + 1e-5 * want);
      EXPECT_NEAR(a->reflectance[2], 0.2 * want, 1e-5 + 1e-5 * want);
      EXPECT_NEAR(sheen_albedo(Float(mu), Float(r)), want, 1e-5 + 1e-5 * want);
    }
  EXPECT_FALSE(sheen(0.5).albedo(at(0.5, 0), TransportMode::Importance));
}

// Energy: R ≤ 1 for every view angle and roughness, extremes included, and the fit's
// negative dip (r in (0.041, 0.132)) clamped to 0.
TEST(Sheen, AlbedoWithinZeroAndOneEverywhere) {
  double lo = 1, hi = 0;
  for (int i = 0; i <= 400; ++i)
    for (int j = 0; j <= 400; ++j) {
      const Float mu = Float(i / 400.0), r = j == 0 ? Float(1e-7) : Float(j / 400.0);
      const Float e = sheen_albedo(mu, r);
      lo = std::min(lo, double(e));
      hi = std::max(hi, double(e));
    }
  EXPECT_GE(lo, 0.0);
  EXPECT_LE(hi, 1.0);
  EXPECT_NEAR(hi, published_R(0, 1), 1e-5);  // the largest: grazing, r = 1 (0.745)
}

// The build-time table of E_avg(r) = 2 ∫ R μ dμ against Simpson's rule here.
TEST(Sheen, AverageAlbedoTable) {
  for (double r : {0.0, 0.01, 0.1, 0.37, 0.5, 0.9, 1.0}) {
    const int n = 20000;
    double sum = 0;
    for (int i = 0; i <= n; ++i) {
      const double mu = double(i) / n, w = (i == 0 || i == n) ? 1 : (i % 2 ? 4 : 2);
      sum += w * 2 * mu * published_R(mu, r);
    }
    const double want = sum / (3.0 * n);
    // Linear interpolation between entries 1/99 apart: the curvature in r bounds it.
    EXPECT_NEAR(sheen_average_albedo(Float(r)), want, 2e-4 + 2e-3 * want) << "r " << r;
  }
}

// Importance mode (the adjoint) is sampled by gonio's own mixture: the hemispherical
// albedo it estimates is the same double integral as radiance mode's, 2 ∫ R μ dμ.
TEST(Sheen, ImportanceModeHemisphericalAlbedoIsTheAverage) {
  for (double r : {0.1, 0.3, 1.0}) {
    const int n = 20000;
    double sum = 0;
    for (int i = 0; i <= n; ++i) {
      const double mu = double(i) / n, w = (i == 0 || i == n) ? 1 : (i % 2 ? 4 : 2);
      sum += w * 2 * mu * published_R(mu, r);
    }
    const double want = 0.5 * sum / (3.0 * n);
    const BxDF b = sheen(r, Color(0.5f));
    // Not reciprocal: the albedo is the view's (radiance mode, its closed form), the
    // light's (importance mode, sampled) follows (reflectance.h).
    const AlbedoEstimate e = hemispherical_albedo(b, false, {2'000'000, 5});
    EXPECT_FALSE(e.exact);
    ASSERT_TRUE(e.light.has_value());
    EXPECT_NEAR(e.light->albedo[0], want, 5 * e.light->se_albedo[0] + 1e-6) << "r " << r;
    EXPECT_NEAR(e.albedo[0], want, 2e-4 + 2e-3 * want) << "r " << r;
  }
}

// Roughness near 0 (below the fits' 0.01: the lobe of 0.01) and at 1: finite,
// non-negative f, pdf and weights at normal, grazing and denormal directions.
TEST(Sheen, ExtremeRoughnessFinite) {
  const std::vector<Vec3> dirs = {{0, 0, 1}, {1, 0, 0}, normalize(Vec3{1, 0, 1e-7f}), normalize(Vec3{0.6f, 0.8f, 1e-30f}),
                                  normalize(Vec3{1e-30f, 0, 1}), {0.6f, 0, 0.8f}, {0, -0.8f, -0.6f},
                                  normalize(Vec3{-1, 2, 1e-3f})};
  for (double r : {1e-30, 1e-7, 1e-3, 0.01, 0.0100001, 0.5, 0.999999, 1.0}) {
    const SheenBxDF m = sheen(r);
    for (const auto& wo : dirs) {
      for (const auto& wi : dirs)
        for (auto mode : {TransportMode::Radiance, TransportMode::Importance}) {
          const Float f = m.f(wo, wi, mode)[0], p = m.pdf(wo, wi, mode);
          EXPECT_TRUE(std::isfinite(f) && f >= 0) << r;
          EXPECT_TRUE(std::isfinite(p) && p >= 0) << r;
        }
      for (float u : {0.0f, 0.5f, 0.99999994f})
        for (auto mode : {TransportMode::Radiance, TransportMode::Importance})
          if (auto s = m.sample(wo, u, u, 1 - u, mode)) {
            EXPECT_TRUE(std::isfinite(s->weight[0]) && s->weight[0] >= 0 && s->weight[0] < 1e6f) << r;
            EXPECT_GT(s->pdf, 0);
            EXPECT_GT(s->wi.z * wo.z, 0);
          }
    }
  }
  // Below 0.01 the lobe is that of 0.01.
  const Vec3 wo = at(0.4, 0), wi = at(0.3, 2.0);
  EXPECT_EQ(sheen(1e-6).f(wo, wi)[0], sheen(0.01).f(wo, wi)[0]);
}

// Radiance-mode samples carry exactly color R(μo) (the LTC is sampled exactly).
TEST(Sheen, RadianceSamplesCarryTheAlbedo) {
  Pcg32 rng(3);
  for (double r : {0.05, 0.3, 1.0})
    for (double mu : {0.9, 0.4, 0.02}) {
      const SheenBxDF m = sheen(r, Color(0.3f, 0.6f, 0.9f));
      const Vec3 wo = at(mu, 2.5);
      for (int k = 0; k < 1000; ++k) {
        const auto s = m.sample(wo, rng.next_float(), rng.next_float(), rng.next_float());
        if (!s) continue;
        EXPECT_NEAR(s->weight[1], 0.6 * published_R(mu, r), 1e-5);
        EXPECT_NEAR(s->pdf, m.pdf(wo, s->wi), 1e-4 * s->pdf);
      }
    }
}

// Not reciprocal by construction. The largest relative error over a grid of θo, θi in
// 1°..89° (4° steps) and Δφ in 0°..180° (15° steps), per roughness, published in
// docs/testing.md; the validator reports reciprocity as not applicable, with the reason.
TEST(Sheen, ReciprocityErrorMeasuredAndReportedNotApplicable) {
  for (double r : {0.01, 0.1, 0.3, 0.5, 0.7, 1.0}) {
    const SheenBxDF m = sheen(r);
    double worst = 0;
    for (int to = 1; to < 90; to += 4)
      for (int ti = 1; ti < 90; ti += 4)
        for (int dp = 0; dp <= 180; dp += 15) {
          const Vec3 wo = direction_from_angles(Float(to * kPiD / 180), 0);
          const Vec3 wi = direction_from_angles(Float(ti * kPiD / 180), Float(dp * kPiD / 180));
          const double a = m.f(wo, wi)[0], b = m.f(wi, wo)[0], mx = std::max(a, b);
          if (mx > 0) worst = std::max(worst, std::abs(a - b) / mx);
          // Importance mode is the exact adjoint.
          EXPECT_EQ(m.f(wo, wi, TransportMode::Importance)[0], m.f(wi, wo)[0]);
        }
    std::printf("sheen roughness %g: largest relative reciprocity error %.4f\n", r, worst);
    EXPECT_GT(worst, 0.2) << r;
  }
  const BxDF b = parse_material(R"({"type":"sheen","roughness":0.5})");
  EXPECT_FALSE(b.nonreciprocal_reason().empty());
  const PropertyResult p = check_reciprocity(b, {1, 0.05});
  EXPECT_FALSE(p.applicable);
  EXPECT_TRUE(p.pass) << p.detail;
  EXPECT_FALSE(p.figure);
  EXPECT_NE(p.detail.find("not applicable"), std::string::npos) << p.detail;
  // A blend with a sheen part inherits it; a reciprocal model is unaffected.
  const BxDF blend = parse_material(R"({"type":"blend","weight":0.5,"bsdfs":[{"type":"diffuse"},{"type":"sheen"}]})");
  EXPECT_FALSE(check_reciprocity(blend, {1, 0.05}).applicable);
  EXPECT_TRUE(check_reciprocity(parse_material(R"({"type":"diffuse"})"), {1, 0.05}).applicable);
}

TEST(Sheen, ParsedWithRegistryDefaultsAndRanges) {
  const BxDF b = parse_material(R"({"type":"sheen"})");
  const auto* m = std::get_if<SheenBxDF>(&b.models());
  ASSERT_TRUE(m);
  EXPECT_EQ(m->roughness, 0.5f);
  EXPECT_EQ(m->color[0], 1.0f);
  for (const char* bad : {R"({"type":"sheen","roughness":0})", R"({"type":"sheen","roughness":1.5})",
                          R"({"type":"sheen","color":-0.1})", R"({"type":"sheen","color":[1,2,0]})"}) {
    try {
      parse_material(bad);
      ADD_FAILURE() << bad;
    } catch (const std::exception& e) {
      const std::string what = e.what();
      EXPECT_TRUE(what.find("roughness") != std::string::npos || what.find("color") != std::string::npos) << what;
    }
  }
}

}  // namespace sheen_test
}  // namespace gonio
