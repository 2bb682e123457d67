// The hair fibre (bxdf/hair.h; Chiang et al. 2016; SPEC §2) against values made here
// without the model's code: M_p against the direct integral of the spherical Gaussian
// (von Mises–Fisher lobe) over the azimuth about the fibre, N_p against the paper's
// trimmed logistic normalised by quadrature, the Gauss–Legendre nodes against the
// polynomials they must integrate exactly, the roughness and absorption mappings against
// the papers' coefficients typed in again; then the white furnace (σa = 0: ∫ f |cos θi|
// over the whole sphere is 1) and the pdf's integral by quadrature over the sphere, χ²
// per lobe, sampled weights against f cos / pdf, finite values at every degenerate
// direction, the parser's rules and chiang_hair_bsdf's mapping.

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <string>
#include <vector>

#include "gonio/bxdf.h"
#include "gonio/error.h"
#include "gonio/material.h"
#include "gonio/math/warp.h"
#include "gonio/spectral_material.h"
#include "gonio/rng.h"
#include "gonio/validate.h"
#include "test_scale.h"

namespace gonio {
namespace hair_test {

constexpr double kPiH = 3.14159265358979323846;

// d'Eon et al. 2011's M_p by its definition: the vMF lobe of concentration κ = 1/v about
// the direction (−θo) on the sphere, κ/(4π sinh κ) exp(κ cos(angle)), integrated over the
// azimuth about the fibre (dφ; M_p is a density in θi with the measure cos θi dθi).
// Written with e^(−κ) taken out so that no exponential overflows.
double mp_direct(double th_i, double th_o, double v) {
  const double k = 1 / v;
  const int n = 4096;
  double sum = 0;
  for (int j = 0; j < n; ++j) {
    const double phi = 2 * kPiH * (j + 0.5) / n;
    // cos of the angle between (θi, φ) and the mirror direction (−θo, 0)
    const double c = std::cos(th_i) * std::cos(th_o) * std::cos(phi) - std::sin(th_i) * std::sin(th_o);
    sum += std::exp(k * (c - 1));
  }
  sum *= 2 * kPiH / n;
  return k / (2 * kPiH * (1 - std::exp(-2 * k))) * sum;
}

TEST(Hair, LongitudinalMatchesTheSphericalGaussianIntegral) {
  for (double v : {0.002, 0.01, 0.05, 0.1, 0.3, 1.0, 5.0, 27.0})
    for (double to : {-1.2, -0.3, 0.0, 0.4, 1.5})
      for (double ti : {-1.4, -0.5, -0.1, 0.0, 0.25, 0.9, 1.55}) {
        const double want = mp_direct(ti, to, v);
        const double got = hair::longitudinal(Float(std::sin(ti)), Float(std::cos(ti)), Float(std::sin(to)),
                                              Float(std::cos(to)), Float(v));
        if (want < 1e-30) {
          EXPECT_LT(got, 1e-25) << v << " " << to << " " << ti;
          continue;
        }
        EXPECT_NEAR(got / want, 1, 3e-4) << "v " << v << " theta_o " << to << " theta_i " << ti;
      }
}

// The paper's trimmed logistic (Chiang §4.2, eqs. 11-12), its normaliser by quadrature.
double logistic(double x, double s) {
  const double e = std::exp(-std::abs(x) / s);
  return e / (s * (1 + e) * (1 + e));
}
double trimmed(double x, double s) {
  static double cached_s = -1, z = 0;
  if (s != cached_s) {
    const int n = 20000;
    z = 0;
    for (int j = 0; j < n; ++j) z += logistic(-kPiH + 2 * kPiH * (j + 0.5) / n, s);
    z *= 2 * kPiH / n;
    cached_s = s;
  }
  return logistic(x, s) / z;
}

TEST(Hair, AzimuthalIsThePapersTrimmedLogistic) {
  for (double s : {0.02, 0.1, 0.4, 2.0})
    for (int p = 0; p < 3; ++p)
      for (double h : {-0.9, 0.0, 0.35}) {
        const double eta = 1.55, th_o = 0.3;
        // Φ(p, h) = 2p γt − 2γo + pπ with sin γt = h / η′, η′ = √(η² − sin²θo)/cos θo.
        const double etap = std::sqrt(eta * eta - std::sin(th_o) * std::sin(th_o)) / std::cos(th_o);
        const double go = std::asin(h), gt = std::asin(h / etap);
        const double Phi = 2 * p * gt - 2 * go + p * kPiH;
        for (double dphi : {-3.0, -1.0, 0.0, 0.5, 2.5, 3.1}) {
          double x = dphi - Phi;
          while (x > kPiH) x -= 2 * kPiH;
          while (x < -kPiH) x += 2 * kPiH;
          const double want = trimmed(x, s);
          const double got = hair::azimuthal(Float(dphi), p, Float(s), Float(go), Float(gt));
          EXPECT_NEAR(got, want, 2e-4 * want + 1e-30) << s << " " << p << " " << h << " " << dphi;
        }
      }
  // Its sampling inverts the CDF: u = ∫_{−π}^{x(u)} l_t.
  for (double s : {0.05, 0.5})
    for (double u : {0.1, 0.5, 0.93}) {
      const double x = hair::sample_trimmed_logistic(Float(u), Float(s));
      const int n = 20000;
      double c = 0;
      for (int j = 0; j < n; ++j) c += trimmed(-kPiH + (x + kPiH) * (j + 0.5) / n, s);
      c *= (x + kPiH) / n;
      EXPECT_NEAR(c, u, 2e-4) << s << " " << u;
    }
}

TEST(Hair, GaussLegendreRuleIsExactForDegree15) {
  for (int d = 0; d <= 15; ++d) {
    double sum = 0;
    for (int k = 0; k < hair::kGaussPoints; ++k) sum += 2 * double(hair::gauss_prob(k)) * std::pow(hair::gauss_node(k), d);
    EXPECT_NEAR(sum, d % 2 ? 0.0 : 2.0 / (d + 1), 2e-6) << d;
  }
}

TEST(Hair, RoughnessAndAbsorptionMappingsArePapers) {
  // Chiang et al. 2016 eqs. 7-9, typed in again.
  for (double b : {0.05, 0.3, 0.7, 1.0}) {
    const double v = std::pow(0.726 * b + 0.812 * b * b + 3.7 * std::pow(b, 20), 2);
    const double s = std::sqrt(kPiH / 8) * (0.265 * b + 1.194 * b * b + 5.372 * std::pow(b, 22));
    EXPECT_NEAR(hair::variance_from_beta_m(Float(b)) / v, 1, 1e-5) << b;
    EXPECT_NEAR(hair::scale_from_beta_n(Float(b)) / s, 1, 1e-5) << b;
    for (double c : {0.05, 0.5, 0.9}) {
      const double den = 5.969 - 0.215 * b + 2.532 * b * b - 10.73 * std::pow(b, 3) + 5.574 * std::pow(b, 4) +
                         0.245 * std::pow(b, 5);
      const double sa = std::pow(std::log(c) / den, 2);
      EXPECT_NEAR(hair::sigma_a_from_color(Float(c), Float(b)) / sa, 1, 1e-5) << b << " " << c;
    }
  }
  // d'Eon et al. 2011's melanin coefficients (as pbrt-v4 gives them in RGB).
  const BxDF m = parse_material(R"({"type":"hair","eumelanin":0.8,"pheomelanin":2})");
  const auto& hb = std::get<HairBxDF>(m.models());
  const double eu[3] = {0.419, 0.697, 1.37}, ph[3] = {0.187, 0.4, 1.05};
  for (int c = 0; c < 3; ++c) EXPECT_NEAR(hb.sigma_a[c], 0.8 * eu[c] + 2 * ph[c], 1e-5);
  // No absorption given: eumelanin 1.3.
  const BxDF dm = parse_material(R"({"type":"hair"})");
  const auto& d = std::get<HairBxDF>(dm.models());
  for (int c = 0; c < 3; ++c) EXPECT_NEAR(d.sigma_a[c], 1.3 * eu[c], 1e-5);
  // A colour: eq. 9 with beta_n.
  const BxDF cm = parse_material(R"({"type":"hair","color":[0.6,0.4,0.2],"beta_n":0.5})");
  const auto& col = std::get<HairBxDF>(cm.models());
  EXPECT_NEAR(col.sigma_a[2], hair::sigma_a_from_color(0.2f, 0.5f), 1e-6);
}

// ∫ f |cos θi| dωi and ∫ pdf dωi over the whole sphere by the midpoint rule in
// (sin θi, φi) (dω = d sin θi dφ), with θ, φ as the fibre's (x the axis).
struct SphereIntegrals {
  Color albedo;
  double pdf;
};
SphereIntegrals integrate_sphere(const BxDF& b, const Vec3& wo, int nu, int nphi) {
  SphereIntegrals r{Color(0.0f), 0};
  double a[3] = {0, 0, 0};
  for (int i = 0; i < nu; ++i) {
    const double u = -1 + 2 * (i + 0.5) / nu, c = std::sqrt(1 - u * u);
    for (int j = 0; j < nphi; ++j) {
      const double phi = -kPiH + 2 * kPiH * (j + 0.5) / nphi;
      const Vec3 wi{Float(u), Float(c * std::cos(phi)), Float(c * std::sin(phi))};
      const BSDFEval e = b.eval(wo, wi);
      for (int k = 0; k < 3; ++k) a[k] += double(e.f[k]) * std::abs(double(wi.z));
      r.pdf += e.pdf;
    }
  }
  const double cell = 2.0 / nu * 2 * kPiH / nphi;
  for (int k = 0; k < 3; ++k) r.albedo[k] = Float(a[k] * cell);
  r.pdf *= cell;
  return r;
}

TEST(Hair, WhiteFurnaceAndPdfIntegrateToOne) {
  // σa = 0: Σ A_p = 1 and each M_p N_p is normalised, so every h and wo gives 1 (Chiang
  // §4; pbrt-v4's white furnace test). β from 0.1 to 1, several tilts.
  const Vec3 wo = normalize(Vec3{0.3f, 0.5f, -0.8f});
  for (const char* beta : {"0.1", "0.3", "0.6", "1"})
    for (const char* alpha : {"0", "4", "-10"}) {
      const std::string j = std::string(R"({"type":"hair","sigma_a":0,"h":0.37,"beta_m":)") + beta + ",\"beta_n\":" +
                            beta + ",\"alpha\":" + alpha + "}";
      const BxDF b = parse_material(j);
      const bool narrow = std::string(beta) == "0.1";
      const auto r = integrate_sphere(b, wo, narrow ? 600 : 200, narrow ? 1500 : 400);
      for (int k = 0; k < 3; ++k) EXPECT_NEAR(r.albedo[k], 1, 0.01) << j;
      EXPECT_NEAR(r.pdf, 1, 0.01) << j;
    }
  // Averaged over h (the Gauss–Legendre rule), another direction.
  const BxDF avg = parse_material(R"({"type":"hair","sigma_a":0,"beta_m":0.5,"beta_n":0.5,"alpha":3})");
  const auto r = integrate_sphere(avg, normalize(Vec3{-0.6f, 0.2f, 0.7f}), 150, 300);
  for (int k = 0; k < 3; ++k) EXPECT_NEAR(r.albedo[k], 1, 0.01);
  EXPECT_NEAR(r.pdf, 1, 0.01);
  // Absorbing: less than 1, and the pdf still integrates to 1.
  const BxDF brown = parse_material(R"({"type":"hair","eumelanin":0.5,"beta_m":0.4,"beta_n":0.4})");
  const auto rb = integrate_sphere(brown, wo, 150, 300);
  EXPECT_LT(rb.albedo.max_component(), 0.99);
  EXPECT_GT(rb.albedo.min_component(), 0.02);
  EXPECT_NEAR(rb.pdf, 1, 0.01);
}

TEST(Hair, SampledWeightIsFCosOverPdf) {
  Pcg32 rng(7, 3);
  for (const char* j : {R"({"type":"hair"})", R"({"type":"hair","h":-0.6,"beta_m":[0.2,0.5,0.8],"alpha":-5})",
                        R"({"type":"hair","color":[0.8,0.5,0.2],"tint_R":0.3,"tint_TT":[1,0,0]})"}) {
    const BxDF b = parse_material(j);
    for (int i = 0; i < 2000; ++i) {
      const Vec3 wo = square_to_uniform_sphere(rng.next_float(), rng.next_float());
      const auto s = b.sample(wo, rng.next_float(), rng.next_float(), rng.next_float());
      if (!s) continue;
      const BSDFEval e = b.eval(wo, s->wi);
      ASSERT_GT(e.pdf, 0);
      EXPECT_NEAR(s->pdf / e.pdf, 1, 1e-5);
      for (int k = 0; k < 3; ++k)
        EXPECT_NEAR(s->weight[k], e.f[k] * std::abs(s->wi.z) / e.pdf, 1e-4 * (1 + s->weight[k])) << j;
    }
  }
}

// χ² of each lobe alone (the others' tints 0) and of the whole model: samples binned on
// a grid of equal solid angle over the whole sphere (sin θ, φ about the fibre), expected
// counts from pdf() by a 4 × 4 midpoint rule per cell, cells expected to hold < 5 pooled;
// Pearson's statistic against the χ² quantile (Wilson–Hilferty) at significance 1e-4.
double pearson_p_bound(const BxDF& b, const Vec3& wo, int n, std::uint64_t seed, double* dof_out) {
  constexpr int nu = 24, nphi = 48, sub = 4;
  std::vector<double> expected(nu * nphi, 0.0), observed(nu * nphi, 0.0);
  for (int i = 0; i < nu; ++i)
    for (int j = 0; j < nphi; ++j) {
      double sum = 0;
      for (int a = 0; a < sub; ++a)
        for (int c = 0; c < sub; ++c) {
          const double u = -1 + 2 * (i + (a + 0.5) / sub) / nu, r = std::sqrt(1 - u * u);
          const double phi = -kPiH + 2 * kPiH * (j + (c + 0.5) / sub) / nphi;
          sum += b.pdf(wo, Vec3{Float(u), Float(r * std::cos(phi)), Float(r * std::sin(phi))});
        }
      expected[size_t(i * nphi + j)] = sum / (sub * sub) * (2.0 / nu) * (2 * kPiH / nphi) * n;
    }
  Pcg32 rng(seed, 11);
  for (int k = 0; k < n; ++k) {
    const auto s = b.sample(wo, rng.next_float(), rng.next_float(), rng.next_float());
    if (!s) continue;
    const int i = std::min(nu - 1, int((s->wi.x + 1) / 2 * nu));
    const double phi = std::atan2(double(s->wi.z), double(s->wi.y));
    const int j = std::min(nphi - 1, int((phi + kPiH) / (2 * kPiH) * nphi));
    observed[size_t(i * nphi + j)] += 1;
  }
  double chi2 = 0, pe = 0, po = 0;
  int cells = 0;
  for (size_t c = 0; c < expected.size(); ++c) {
    if (expected[c] < 5) {
      pe += expected[c];
      po += observed[c];
      continue;
    }
    chi2 += (observed[c] - expected[c]) * (observed[c] - expected[c]) / expected[c];
    ++cells;
  }
  if (pe > 0) {
    chi2 += (po - pe) * (po - pe) / std::max(pe, 1.0);
    ++cells;
  }
  const double dof = cells - 1;
  *dof_out = dof;
  // Wilson–Hilferty: the 1 − 1e-4 quantile of χ²(dof), z = 3.719.
  const double q = dof * std::pow(1 - 2 / (9 * dof) + 3.719 * std::sqrt(2 / (9 * dof)), 3);
  return chi2 / q;
}

TEST(Hair, SamplingMatchesPdfPerLobe) {
  const int n = int(test::scaled(100000, 20000));
  for (const char* j : {R"({"type":"hair","h":0.3,"tint_TT":0,"tint_TRT":0,"beta_m":0.2,"beta_n":0.3})",
                        R"({"type":"hair","h":0.3,"tint_R":0,"tint_TRT":0,"sigma_a":0.1,"beta_m":0.2})",
                        R"({"type":"hair","h":-0.5,"tint_R":0,"tint_TT":0,"sigma_a":0.1,"alpha":6})",
                        R"({"type":"hair","h":0.8,"color":[0.7,0.5,0.3],"beta_m":0.6,"beta_n":0.8})",
                        R"({"type":"hair","color":[0.7,0.5,0.3]})"}) {
    const BxDF b = parse_material(j);
    for (const Vec3& wo : {normalize(Vec3{0.4f, 0.5f, 0.7f}), normalize(Vec3{-0.8f, -0.3f, 0.2f})}) {
      double dof = 0;
      const double ratio = pearson_p_bound(b, wo, n, 5, &dof);
      EXPECT_LT(ratio, 1) << j << ": chi2 / quantile " << ratio << " (dof " << dof << ")";
      EXPECT_GT(dof, 20) << j;
    }
  }
}

// The validator's properties that a fibre keeps (finite, consistency, weights; isotropy
// measured about its axis; reciprocity's adjoint), at a fixed h and reduced counts.
TEST(Hair, ValidatorPropertiesHold) {
  ValidationOptions opt;
  opt.scale = 0.02 * double(test::scaled(1000, 100)) / 1000;
  const BxDF b = parse_material(R"({"type":"hair","h":0.6,"color":[0.8,0.6,0.3],"beta_m":0.25,"alpha":-4})");
  for (const auto& p : {check_finite(b, opt), check_consistency(b, opt), check_weights(b, opt),
                        check_isotropy(b, opt), check_reciprocity(b, opt)})
    EXPECT_TRUE(p.pass) << p.name << ": " << p.detail;
  EXPECT_FALSE(check_isotropy(b, opt).applicable);
  EXPECT_FALSE(check_reciprocity(b, opt).applicable);
}

TEST(Hair, FiniteAtDegenerateDirections) {
  const std::vector<Vec3> dirs = {{1, 0, 0}, {-1, 0, 0}, {0, 1, 0}, {0, 0, 1}, {0, 0, -1},
                                  normalize(Vec3{1, 1e-7f, 0}), normalize(Vec3{0.6f, 0.8f, 0}),
                                  normalize(Vec3{0, -0.8f, 1e-8f})};
  for (const char* j : {R"({"type":"hair","beta_m":0.01,"beta_n":0.01,"alpha":60})",
                        R"({"type":"hair","h":1,"sigma_a":0})", R"({"type":"hair","h":-1,"beta_m":1,"beta_n":1})",
                        R"({"type":"chiang_hair_bsdf","roughness_R":[0,0],"cuticle_angle":1})"}) {
    const BxDF b = parse_material(j);
    for (const auto& wo : dirs)
      for (const auto& wi : dirs)
        for (auto mode : {TransportMode::Radiance, TransportMode::Importance}) {
          const BSDFEval e = b.eval(wo, wi, mode);
          EXPECT_TRUE(e.f.is_finite() && e.f.min_component() >= 0) << j;
          EXPECT_TRUE(std::isfinite(e.pdf) && e.pdf >= 0) << j;
          for (Float u : {0.0f, 0.5f, kOneMinusEpsilon}) {
            const auto s = b.sample(wo, u, u, 1 - u, mode);
            if (s) {
              EXPECT_TRUE(s->weight.is_finite() && std::isfinite(s->pdf)) << j;
            }
          }
        }
  }
}

TEST(Hair, ImportanceModeIsTheAdjoint) {
  const BxDF b = parse_material(R"({"type":"hair","alpha":5,"color":0.4})");
  const Vec3 a = normalize(Vec3{0.2f, 0.7f, 0.3f}), c = normalize(Vec3{-0.5f, 0.1f, -0.6f});
  // f_imp(a, c) |c.z| = S(c, a) = f(c, a) |a.z|.
  const Color imp = b.f(a, c, TransportMode::Importance) * std::abs(c.z),
              rad = b.f(c, a, TransportMode::Radiance) * std::abs(a.z);
  for (int k = 0; k < 3; ++k) EXPECT_NEAR(imp[k], rad[k], 1e-6 * rad[k]);
  EXPECT_FALSE(b.nonreciprocal_reason().empty());
  EXPECT_TRUE(b.is_fibre());
}

TEST(Hair, ParserRules) {
  EXPECT_THROW(parse_material(R"({"type":"hair","sigma_a":1,"color":0.5})"), InputError);
  EXPECT_THROW(parse_material(R"({"type":"hair","color":0.5,"eumelanin":1})"), InputError);
  EXPECT_THROW(parse_material(R"({"type":"hair","beta_m":0})"), InputError);
  EXPECT_THROW(parse_material(R"({"type":"hair","beta_n":[0.1,0.2]})"), InputError);
  EXPECT_THROW(parse_material(R"({"type":"hair","alpha":90})"), InputError);
  EXPECT_THROW(parse_material(R"({"type":"hair","eta":1})"), InputError);
  EXPECT_THROW(parse_material(R"({"type":"hair","h":1.5})"), InputError);
  EXPECT_THROW(parse_material(R"({"type":"chiang_hair_bsdf","roughness_R":0.1})"), InputError);
  EXPECT_THROW(parse_material(R"({"type":"chiang_hair_bsdf","beta_m":0.1})"), InputError);
  try {
    parse_material(R"({"type":"hair","sigma_a":1,"color":0.5})");
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("sigma_a"), std::string::npos) << e.what();
  }
  // One β_m: TT and TRT get a quarter and four times R's variance (Marschner's widths).
  const BxDF mm = parse_material(R"({"type":"hair","beta_m":0.4})");
  const auto& m = std::get<HairBxDF>(mm.models());
  EXPECT_NEAR(m.v[1], m.v[0] / 4, 1e-7);
  EXPECT_NEAR(m.v[2], 4 * m.v[0], 1e-6);
  EXPECT_EQ(m.v[3], m.v[2]);
  // An array: each lobe its own.
  const BxDF am = parse_material(R"({"type":"hair","beta_m":[0.2,0.4,0.6]})");
  const auto& a = std::get<HairBxDF>(am.models());
  EXPECT_NEAR(a.v[1], hair::variance_from_beta_m(0.4f), 1e-7);
}

TEST(Hair, ChiangHairBsdfIsTheSameModelWithMaterialXInputs) {
  const BxDF mx = parse_material(
      R"({"type":"chiang_hair_bsdf","roughness_R":[0.02,0.3],"roughness_TT":[0.01,0.2],"roughness_TRT":[0.08,0.5],)"
      R"("cuticle_angle":0.53,"ior":1.6,"absorption_coefficient":[0.2,0.4,0.9],"tint_TT":[1,0.5,0.5]})");
  HairBxDF want;
  want.v = {0.02f, 0.01f, 0.08f, 0.08f};
  // MaterialX's mx_hair_trimmed_logistic scales s by sqrt(pi/8) = 0.626657.
  want.s = {Float(0.3 * 0.626657), Float(0.2 * 0.626657), Float(0.5 * 0.626657)};
  want.prepare();
  want.set_alpha(Float(0.03 * kPiH));
  want.eta = 1.6f;
  want.sigma_a = Color(0.2f, 0.4f, 0.9f);
  want.tint[1] = Color(1.0f, 0.5f, 0.5f);
  const BxDF w = want;
  Pcg32 rng(3, 1);
  for (int i = 0; i < 50; ++i) {
    const Vec3 wo = square_to_uniform_sphere(rng.next_float(), rng.next_float());
    const Vec3 wi = square_to_uniform_sphere(rng.next_float(), rng.next_float());
    const Color a = mx.f(wo, wi), b = w.f(wo, wi);
    for (int k = 0; k < 3; ++k) EXPECT_NEAR(a[k], b[k], 1e-4 * (1 + b[k]));
  }
}

TEST(Hair, SpectralModeMatchesRgbForGreyAbsorption) {
  // A grey σa and white tints: every wavelength equals the RGB channels.
  const std::string j = R"({"type":"hair","sigma_a":0.3,"beta_m":0.35,"alpha":3})";
  const BxDF rgb = parse_material(j);
  SampledWavelengths wl = SampledWavelengths::sample_uniform(0.3f);
  const MaterialWithSpectra m = parse_material_with_spectra(j);
  SpectralScratch scratch;
  const SpectralBxDF sp = to_spectral(m.bxdf, m.spectra, wl, scratch);
  const Vec3 wo = normalize(Vec3{0.1f, 0.6f, 0.5f}), wi = normalize(Vec3{-0.3f, -0.2f, 0.9f});
  const Color a = rgb.f(wo, wi);
  const SampledSpectrum b = sp.f(wo, wi);
  for (int k = 0; k < 4; ++k) EXPECT_NEAR(b[k], a[0], 1e-5 * (1 + a[0]));
}

}  // namespace hair_test
}  // namespace gonio
