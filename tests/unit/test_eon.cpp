// EON, the energy-preserving Oren–Nayar (Portsmouth, Kutz & Hill, JCGT 14(1), 2025;
// include/gonio/bxdf/eon.h), against numbers made here without the model's code:
//  - Fujii's own form of his lobe (mimosa-pudica.net/improved-oren-nayar.html):
//    L = ρ (A + B s/t), A = 1/(π + (π/2 − 2/3) σ), B = σ A, s = cos φ-term, t = max(cos) if s > 0;
//  - its directional albedo E_F(μ) and average Ē_F by quadrature of that lobe (this file's
//    Gauss–Legendre in cos θi times a uniform rule in φ, split where s/t has its kinks);
//  - the multiple-scattering lobe of the paper (§3) built from those quadratures;
//  - the white furnace: ∫ f cos θi dωi = 1 for ρ = 1 by the same quadrature;
//  - roughness 0 is Lambert to the last bit.
// Sampling is proven by the validator (chi2, pdf_integral, consistency; test_validate.cpp).

#include <gtest/gtest.h>

#include <cmath>
#include <functional>
#include <vector>

#include "../test_common.h"
#include "gonio/bxdf.h"
#include "gonio/material.h"
#include "gonio/validate.h"

namespace gonio {
namespace eon_test {

// Fujii's lobe at ρ = 1, in his notation (not the paper's A_F = π A).
double fujii(double mu_o, double mu_i, double cos_dphi, double sigma) {
  const double A = 1 / (kPiD + (kPiD / 2 - 2.0 / 3) * sigma), B = sigma * A;
  const double s = std::sqrt(1 - mu_o * mu_o) * std::sqrt(1 - mu_i * mu_i) * cos_dphi;
  const double t = s > 0 ? std::max(mu_o, mu_i) : 1;
  return A + B * s / t;
}

// ∫ g(μi, φ) μi dμi dφ over the hemisphere, split at μi = μo (t switches) and at
// φ = ±π/2 (s changes sign), each piece by Gauss–Legendre.
double hemisphere(double mu_o, const std::function<double(double, double)>& g, int n = 48) {
  std::vector<double> xm, wm, xp, wp;
  double sum = 0;
  const double mu_cuts[] = {0, mu_o, 1};
  const double phi_cuts[] = {0, kPiD / 2, kPiD};  // symmetric in φ: twice [0, π]
  for (int a = 0; a < 2; ++a) {
    if (mu_cuts[a + 1] <= mu_cuts[a]) continue;
    gauss_legendre(n, mu_cuts[a], mu_cuts[a + 1], xm, wm);
    for (int b = 0; b < 2; ++b) {
      gauss_legendre(n, phi_cuts[b], phi_cuts[b + 1], xp, wp);
      for (size_t i = 0; i < xm.size(); ++i)
        for (size_t j = 0; j < xp.size(); ++j) sum += 2 * wm[i] * wp[j] * g(xm[i], xp[j]) * xm[i];
    }
  }
  return sum;
}

double fujii_albedo(double mu_o, double sigma) {
  return hemisphere(mu_o, [&](double mu_i, double phi) { return fujii(mu_o, mu_i, std::cos(phi), sigma); });
}

// Ē_F = 2 ∫ E_F(μ) μ dμ by Gauss–Legendre over the (smooth) E_F.
double fujii_average(double sigma) {
  std::vector<double> x, w;
  gauss_legendre(24, 0, 1, x, w);
  double s = 0;
  for (size_t i = 0; i < x.size(); ++i) s += 2 * w[i] * x[i] * fujii_albedo(x[i], sigma);
  return s;
}

Vec3 dir(double mu, double phi) {
  const double s = std::sqrt(1 - mu * mu);
  return Vec3{Float(s * std::cos(phi)), Float(s * std::sin(phi)), Float(mu)};
}

EonBxDF eon_model(Color rho, double r) {
  EonBxDF m;
  m.reflectance = rho;
  m.roughness = Float(r);
  return m;
}

// The exact E_F of the paper (§3) against the quadrature of Fujii's lobe.
TEST(Eon, ExactFonAlbedoMatchesQuadratureOfFujiisLobe) {
  for (double r : {0.1, 0.5, 1.0})
    for (double mu : {0.02, 0.1, 0.3, 0.5, 0.8, 0.999, 1.0}) {
      const double want = fujii_albedo(mu, r);
      EXPECT_NEAR(eon::albedo_fon(Float(mu), Float(r)), want, 2e-6) << "r=" << r << " mu=" << mu;
    }
  // μ → 0: every direction reflected (E_F = 1); no 0/0 at μ = 0 itself.
  EXPECT_NEAR(eon::albedo_fon(0, 1), 1, 1e-6);
  EXPECT_NEAR(eon::albedo_fon(1e-7f, 1), 1, 1e-6);
}

TEST(Eon, AverageFonAlbedoMatchesQuadrature) {
  for (double r : {0.2, 0.6, 1.0}) EXPECT_NEAR(eon::average_albedo_fon(Float(r)), fujii_average(r), 2e-6) << r;
}

// The model's f = ρ × Fujii + the paper's multiple-scattering lobe, with E_F and Ē_F from
// this file's quadrature: f_ms = ρ_ms/π (1 − E_F(μo))(1 − E_F(μi))/(1 − Ē_F),
// ρ_ms = ρ² Ē_F / (1 − ρ (1 − Ē_F)).
TEST(Eon, ValueIsFujiiPlusTheMultipleScatteringLobe) {
  const Color rho(0.9f, 0.5f, 0.15f);
  for (double r : {0.3, 1.0}) {
    const EonBxDF m = eon_model(rho, r);
    const double avg = fujii_average(r);
    for (double mu_o : {0.15, 0.6, 0.95})
      for (double mu_i : {0.05, 0.4, 0.9})
        for (double dphi : {0.3, 2.0, 3.1}) {
          const Vec3 wo = dir(mu_o, 0.4), wi = dir(mu_i, 0.4 + dphi);
          const Color f = m.f(wo, wi);
          const double eo = fujii_albedo(mu_o, r), ei = fujii_albedo(mu_i, r);
          for (int c = 0; c < 3; ++c) {
            const double p = rho[c];
            const double rho_ms = p * p * avg / (1 - p * (1 - avg));
            const double want = p * fujii(mu_o, mu_i, std::cos(dphi), r) + rho_ms / kPiD * (1 - eo) * (1 - ei) / (1 - avg);
            EXPECT_NEAR(f[c], want, 2e-6 + 2e-5 * want) << "r=" << r << " mu_o=" << mu_o << " mu_i=" << mu_i;
          }
          // Reciprocal and two-sided.
          EXPECT_NEAR(m.f(wi, wo)[0], f[0], 1e-6 * f[0]);
          EXPECT_NEAR(m.f(Vec3{wo.x, wo.y, -wo.z}, Vec3{wi.x, wi.y, -wi.z})[0], f[0], 1e-6 * f[0]);
        }
  }
}

// ∫ f cos θi dωi = 1 for a white base, at every angle and roughness (the paper's claim),
// by this file's quadrature of the model's f; and the closed-form albedo() agrees.
TEST(Eon, WhiteFurnaceReflectsEverything) {
  for (double r : {0.0, 0.05, 0.3, 0.7, 1.0}) {
    const EonBxDF m = eon_model(Color(1), r);
    for (double theta : {0.0, 20.0, 45.0, 70.0, 85.0, 89.5}) {
      const double mu_o = std::cos(theta * kPiD / 180);
      const Vec3 wo = dir(mu_o, 0);
      const double e = hemisphere(mu_o, [&](double mu_i, double phi) { return double(m.f(wo, dir(mu_i, phi))[0]); });
      EXPECT_NEAR(e, 1, 2e-5) << "r=" << r << " theta=" << theta;
      EXPECT_NEAR(m.albedo(wo).reflectance[0], 1, 2e-6) << "r=" << r << " theta=" << theta;
      EXPECT_EQ(m.albedo(wo).transmittance[0], 0);
    }
  }
}

// A coloured base: albedo() = ρ E_F + ρ_ms (1 − E_F) (the paper's E_EON) against the
// quadrature of f.
TEST(Eon, ColouredAlbedoMatchesQuadrature) {
  const EonBxDF m = eon_model(Color(0.95f, 0.5f, 0.05f), 0.8);
  for (double theta : {0.0, 40.0, 80.0}) {
    const double mu_o = std::cos(theta * kPiD / 180);
    const Vec3 wo = dir(mu_o, 1.0);
    for (int c = 0; c < 3; ++c) {
      const double e = hemisphere(mu_o, [&](double mu_i, double phi) { return double(m.f(wo, dir(mu_i, phi + 1.0))[c]); });
      EXPECT_NEAR(m.albedo(wo).reflectance[c], e, 2e-5) << theta << " channel " << c;
    }
  }
}

// Roughness 0 is Lambert exactly: f = ρ/π, the cosine density, sample weights ρ.
TEST(Eon, RoughnessZeroIsLambert) {
  const Color rho(0.7f, 0.2f, 1.0f);
  const EonBxDF m = eon_model(rho, 0);
  const DiffuseBxDF lambert{rho};
  for (double mu_o : {0.01, 0.5, 1.0})
    for (double mu_i : {0.01, 0.3, 0.99}) {
      const Vec3 wo = dir(mu_o, 0.2), wi = dir(mu_i, 2.5);
      for (int c = 0; c < 3; ++c) EXPECT_EQ(m.f(wo, wi)[c], rho[c] * kInvPi);
      EXPECT_FLOAT_EQ(m.pdf(wo, wi), Float(mu_i / kPiD));
      EXPECT_EQ(m.f(wo, wi)[0], lambert.f(wo, wi)[0]);
    }
  for (float u : {0.1f, 0.5f, 0.9f}) {
    const auto s = m.sample(dir(0.7, 0.3), u, u, 1 - u);
    ASSERT_TRUE(s);
    for (int c = 0; c < 3; ++c) EXPECT_NEAR(s->weight[c], rho[c], 1e-6);
  }
  // albedo = ρ at every angle.
  EXPECT_NEAR(m.albedo(dir(0.3, 0)).reflectance[1], rho[1], 1e-7);
}

// The CLTC density integrates to 1 over the hemisphere less the part of the cosine lobe
// clipped away (0 when d ≤ 0, as the fit gives away from normal incidence), by
// quadrature here; and the mixture's uniform share is the paper's P_u.
TEST(Eon, SamplingDensityIsNormalised) {
  for (double r : {0.2, 1.0})
    for (double mu_o : {0.05, 0.5, 0.9}) {
      const EonBxDF m = eon_model(Color(0.5f), r);
      const Vec3 wo = dir(mu_o, 0.7);
      const double total = hemisphere(mu_o, [&](double mu_i, double phi) {
        return double(m.pdf(wo, dir(mu_i, phi + 0.7))) / mu_i;  // hemisphere() weighs by μi
      }, 64);
      EXPECT_NEAR(total, 1, 2e-4) << "r=" << r << " mu_o=" << mu_o;
    }
}

TEST(Eon, FiniteEverywhere) {
  const Vec3 dirs[] = {{0, 0, 1}, {0.9999999f, 0, 1e-7f}, {1, 0, 0}, {0.6f, 0, -0.8f}, {0, 0, -1},
                       {0.5f, 0.5f, 0.70710678f}, {-0.2f, 0.1f, -1e-7f}, {0.99999f, 0.0f, 0.0044721f}};
  for (double r : {0.0, 1e-7, 1e-3, 0.5, 1.0}) {
    const EonBxDF m = eon_model(Color(1), r);
    for (const Vec3& wo : dirs) {
      for (const Vec3& wi : dirs) {
        const Color f = m.f(wo, wi);
        EXPECT_TRUE(std::isfinite(f[0]) && f[0] >= 0);
        EXPECT_TRUE(std::isfinite(m.pdf(wo, wi)) && m.pdf(wo, wi) >= 0);
      }
      for (float u : {0.0f, 0.05f, 0.5f, kOneMinusEpsilon}) {
        const auto s = m.sample(wo, u, u, 1 - u);
        if (!s) continue;
        EXPECT_TRUE(std::isfinite(s->weight[0]) && s->weight[0] >= 0 && s->pdf > 0);
      }
      EXPECT_TRUE(std::isfinite(m.albedo(wo).reflectance[0]));
    }
  }
}

TEST(Eon, ParserTakesTheRegistrysDefaultsAndRanges) {
  const BxDF d = parse_material(R"({"type":"eon"})");
  const auto* m = std::get_if<EonBxDF>(&d.models());
  ASSERT_TRUE(m);
  EXPECT_FLOAT_EQ(m->reflectance[0], 0.8f);
  EXPECT_EQ(m->roughness, 0);
  EXPECT_THROW(parse_material(R"({"type":"eon","roughness":1.5})"), InputError);
  EXPECT_THROW(parse_material(R"({"type":"eon","roughness":-0.1})"), InputError);
  EXPECT_THROW(parse_material(R"({"type":"eon","reflectance":1.1})"), InputError);
  EXPECT_THROW(parse_material(R"({"type":"eon","sigma":20})"), InputError);
  try {
    parse_material(R"({"type":"eon","roughness":2})");
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("roughness"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("2"), std::string::npos) << e.what();
  }
}

}  // namespace eon_test
}  // namespace gonio
