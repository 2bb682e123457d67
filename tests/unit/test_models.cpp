// The four lecture models against the lecture's own statements: f = ρ/π, the mirror
// direction, Snell's law, Fresnel-weighted lobes, radiance scaling (n_wo/n_wi)² in
// radiance mode only, reciprocity, and finite non-negative values at every edge case.

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <vector>

#include "gonio/bsdf.h"
#include "gonio/bxdf.h"
#include "gonio/math/spherical.h"
#include "gonio/math/warp.h"
#include "gonio/metals.h"
#include "gonio/rng.h"

namespace gonio {
namespace {

constexpr float kDegF = float(kPiD / 180);

Vec3 dir(float theta_deg, float phi_deg) {
  return direction_from_angles(theta_deg * kDegF, phi_deg * kDegF);
}

// Directions a model must survive: normal, grazing, below the horizon, and near-critical.
std::vector<Vec3> adversarial_directions() {
  std::vector<Vec3> v = {{0, 0, 1}, {0, 0, -1}, {1, 0, 0}, {0, 1, 0}, {-1, 0, 0},
                         normalize(Vec3{1, 1, 0}), normalize(Vec3{1, 0, 1e-7f}),
                         normalize(Vec3{1, 0, -1e-7f}), normalize(Vec3{1, 0, 1e-30f}),
                         normalize(Vec3{0, 1, -1e-30f})};
  const float crit = std::asin(1 / 1.5f);
  for (float d : {-1e-6f, 0.f, 1e-6f}) {
    v.push_back(direction_from_angles(crit + d, 0.3f));
    v.push_back(-direction_from_angles(crit + d, 0.3f));
  }
  Pcg32 rng(7);
  for (int i = 0; i < 64; ++i) v.push_back(square_to_uniform_sphere(rng.next_float(), rng.next_float()));
  return v;
}

std::vector<BxDF> all_models() {
  const auto au = *named_metal("Au");
  ConductorBxDF exact{{FresnelModel::Exact, au.eta, au.k, Color(0.f)}};
  ConductorBxDF schlick{{FresnelModel::Schlick, Color(1.f), Color(0.f), Color(0.9f, 0.6f, 0.3f)}};
  return {DiffuseBxDF{Color(0.2f, 0.5f, 0.9f)}, MirrorBxDF{Color(0.8f)}, exact, schlick,
          DielectricBxDF{1.5f}, DielectricBxDF{1 / 1.5f}, DielectricBxDF{1.0f},
          DielectricBxDF{1.0001f}};
}

TEST(Models, FiniteAndNonNegativeEverywhere) {
  const auto dirs = adversarial_directions();
  const float us[] = {0.f, 0.5f, 0.999f, kOneMinusEpsilon};
  for (const auto& m : all_models())
    for (auto mode : {TransportMode::Radiance, TransportMode::Importance})
      for (const auto& wo : dirs) {
        for (const auto& wi : dirs) {
          const Color f = m.f(wo, wi, mode);
          const Float p = m.pdf(wo, wi, mode);
          ASSERT_TRUE(f.is_finite() && f.min_component() >= 0) << m.name();
          ASSERT_TRUE(std::isfinite(p) && p >= 0) << m.name();
        }
        for (float u0 : us)
          for (float u1 : us)
            for (float u2 : us) {
              const auto s = m.sample(wo, u0, u1, u2, mode);
              if (!s) continue;
              ASSERT_TRUE(s->weight.is_finite() && s->weight.min_component() >= 0) << m.name();
              ASSERT_TRUE(std::isfinite(s->pdf) && s->pdf > 0) << m.name();
              ASSERT_TRUE(is_finite(s->wi)) << m.name();
              ASSERT_NEAR(length(s->wi), 1, 1e-5) << m.name();
            }
      }
}

TEST(Models, LambertIsRhoOverPiAndReciprocal) {
  const DiffuseBxDF m{Color(0.2f, 0.5f, 0.9f)};
  const Vec3 wo = dir(30, 10), wi = dir(70, 200);
  const Color f = m.f(wo, wi);
  for (int c = 0; c < 3; ++c) EXPECT_FLOAT_EQ(f[c], m.reflectance[c] / float(kPiD));
  EXPECT_EQ(m.f(wi, wo), f);
  EXPECT_TRUE(m.f(wo, -wi).is_black());              // other side: 0
  EXPECT_EQ(m.f(-wo, -wi), f);                       // two-sided (SPEC §1)
  EXPECT_FLOAT_EQ(m.pdf(wo, wi), wi.z / float(kPiD));  // cosine-weighted
  EXPECT_EQ(m.pdf(wo, -wi), 0.f);
  EXPECT_TRUE(m.f(Vec3{1, 0, 0}, wi).is_black());    // grazing wo belongs to no side
}

TEST(Models, SampleWeightIsFCosOverPdfAndPdfMatches) {
  Pcg32 rng(3);
  const DiffuseBxDF m{Color(0.3f, 0.6f, 0.9f)};
  for (const Vec3& wo : {dir(0, 0), dir(45, 30), dir(89.9f, 0), -dir(60, 100)}) {
    for (int i = 0; i < 2000; ++i) {
      const auto s = m.sample(wo, rng.next_float(), rng.next_float(), rng.next_float());
      if (!s) continue;
      EXPECT_TRUE(same_hemisphere(wo, s->wi));
      EXPECT_NEAR(s->pdf, m.pdf(wo, s->wi), 1e-6f);
      const Color expect = m.f(wo, s->wi) * std::abs(s->wi.z) / s->pdf;
      for (int c = 0; c < 3; ++c) EXPECT_NEAR(s->weight[c], expect[c], 1e-5f);
      EXPECT_FALSE(s->delta);
    }
  }
}

TEST(Models, MirrorReflectsAboutTheNormal) {
  const MirrorBxDF m{Color(0.7f)};
  for (const Vec3& wo : {dir(0, 0), dir(33, 77), dir(85, 300), -dir(40, 10)}) {
    const auto s = m.sample(wo, 0.3f, 0.1f, 0.9f);
    ASSERT_TRUE(s);
    // Lecture §5.2: θr = θi, φr = φi ± π.
    EXPECT_FLOAT_EQ(s->wi.z, wo.z);
    EXPECT_FLOAT_EQ(s->wi.x, -wo.x);
    EXPECT_FLOAT_EQ(s->wi.y, -wo.y);
    EXPECT_TRUE(s->delta);
    EXPECT_EQ(s->weight, Color(0.7f));
    EXPECT_TRUE(m.f(wo, s->wi).is_black());
    EXPECT_EQ(m.pdf(wo, s->wi), 0.f);
  }
  EXPECT_FALSE(m.sample(Vec3{1, 0, 0}, 0.5f, 0.5f, 0.5f));
}

TEST(Models, ConductorWeightIsTheConductorFresnel) {
  const auto au = *named_metal("Au");
  const ConductorBxDF m{{FresnelModel::Exact, au.eta, au.k, Color(0.f)}};
  // RGB-mode gold at 60°: r 0.998753360529, g 0.791853047622 ("Au RGB r/g" of
  // tests/reference/fresnel_reference.py).
  const auto s = m.sample(dir(60, 0), 0.5f, 0.5f, 0.5f);
  ASSERT_TRUE(s);
  EXPECT_NEAR(s->weight[0], 0.998753360529, 1e-5);
  EXPECT_NEAR(s->weight[1], 0.791853047622, 1e-5);
  // Seen from below, the same (two-sided reflection).
  const auto below = m.sample(-dir(60, 0), 0.5f, 0.5f, 0.5f);
  ASSERT_TRUE(below);
  EXPECT_EQ(below->weight, s->weight);
  EXPECT_LT(below->wi.z, 0);
  const ConductorBxDF sch{{FresnelModel::Schlick, Color(1.f), Color(0.f), Color(0.5f)}};
  const auto ss = sch.sample(dir(60, 0), 0.5f, 0.5f, 0.5f);
  EXPECT_NEAR(ss->weight[1], 0.5 + 0.5 * std::pow(0.5, 5), 1e-6);
}

TEST(Models, DielectricReflectsWithProbabilityFAndRefractsBySnell) {
  const DielectricBxDF m{1.5f};
  const Vec3 wo = dir(45, 20);
  const float F = 0.050239911f;  // R(45°, 1.5), tests/reference/fresnel_reference.py
  const auto r = m.sample(wo, F * 0.99f, 0.5f, 0.5f);
  ASSERT_TRUE(r);
  EXPECT_EQ(r->lobe, Lobe::Reflection);
  EXPECT_NEAR(r->pdf, F, 1e-6);
  EXPECT_EQ(r->weight, Color(1.f));
  const auto t = m.sample(wo, F * 1.01f, 0.5f, 0.5f);
  ASSERT_TRUE(t);
  EXPECT_EQ(t->lobe, Lobe::Transmission);
  EXPECT_NEAR(t->pdf, 1 - F, 1e-6);
  EXPECT_TRUE(t->delta);
  EXPECT_LT(t->wi.z, 0);
  EXPECT_NEAR(length(t->wi), 1, 1e-6);
  // Snell: 1 · sin 45° = 1.5 · sin θt; azimuth turned by π.
  EXPECT_NEAR(sin_theta(t->wi), std::sin(45 * kDegF) / 1.5f, 1e-6);
  EXPECT_NEAR(std::cos(phi(t->wi) - phi(wo)), -1, 1e-6);
  // Radiance leaving into air from glass is scaled by (n_wo/n_wi)² = (1/1.5)²; none for importance.
  EXPECT_NEAR(t->weight[0], 1 / 2.25f, 1e-6);
  EXPECT_NEAR(t->eta, 1.5f, 1e-6);
  const auto ti = m.sample(wo, F * 1.01f, 0.5f, 0.5f, TransportMode::Importance);
  EXPECT_NEAR(ti->weight[0], 1.f, 1e-6);
  // From inside, out into the air: scale (1.5/1)².
  const auto out = m.sample(t->wi, 0.9f, 0.5f, 0.5f);
  ASSERT_TRUE(out);
  EXPECT_EQ(out->lobe, Lobe::Transmission);
  EXPECT_NEAR(out->weight[0], 2.25f, 1e-5);
  EXPECT_NEAR(length(out->wi - wo), 0, 1e-5);  // the path reverses exactly
}

TEST(Models, DielectricTotalInternalReflection) {
  const DielectricBxDF m{1.5f};
  const float crit = std::asin(1 / 1.5f) / kDegF;
  for (float th : {crit + 0.01f, 60.f, 89.f}) {
    const Vec3 wo = -dir(th, 0);  // inside the glass
    for (float u0 : {0.f, 0.5f, kOneMinusEpsilon}) {
      const auto s = m.sample(wo, u0, 0.5f, 0.5f);
      ASSERT_TRUE(s);
      EXPECT_EQ(s->lobe, Lobe::Reflection);
      EXPECT_EQ(s->weight, Color(1.f));
    }
  }
  const auto a = m.albedo(-dir(60, 0));
  EXPECT_EQ(a.reflectance, Color(1.f));
  EXPECT_TRUE(a.transmittance.is_black());
}

TEST(Models, DielectricWithEtaOneIsInvisible) {
  const DielectricBxDF m{1.0f};
  const Vec3 wo = dir(50, 40);
  const auto s = m.sample(wo, 0.f, 0.5f, 0.5f);
  ASSERT_TRUE(s);
  EXPECT_EQ(s->lobe, Lobe::Transmission);
  EXPECT_NEAR(length(s->wi + wo), 0, 1e-6);
  EXPECT_NEAR(s->weight[0], 1, 1e-6);
}

TEST(Models, DielectricExpectedWeightIsEnergyInImportanceMode) {
  // E[weight] over u0 = F · 1 + (1 − F) · 1 = 1 in importance mode (energy conserved);
  // in radiance mode it is F + (1 − F)(n_wo/n_wi)².
  const DielectricBxDF m{1.5f};
  for (float th : {0.f, 30.f, 60.f, 85.f}) {
    const Vec3 wo = dir(th, 0);
    const float F = fresnel_dielectric(wo.z, 1.5f);
    double imp = 0, rad = 0;
    const int n = 10000;
    for (int i = 0; i < n; ++i) {
      const float u = (i + 0.5f) / n;
      imp += m.sample(wo, u, 0.5f, 0.5f, TransportMode::Importance)->weight[0];
      rad += m.sample(wo, u, 0.5f, 0.5f, TransportMode::Radiance)->weight[0];
    }
    EXPECT_NEAR(imp / n, 1.0, 1e-6);
    EXPECT_NEAR(rad / n, F + (1 - F) / 2.25, 2e-4);
  }
}

TEST(Models, ThroughTheVariantAndTheWorldFrame) {
  const BxDF m = DiffuseBxDF{Color(0.5f)};
  EXPECT_EQ(m.name(), "diffuse");
  EXPECT_EQ(m.flags(), BxDFFlags::DiffuseReflection);
  EXPECT_TRUE(BxDF(DielectricBxDF{}).relative_eta() == 1.5f);
  // A BSDF on a tilted surface: world directions are taken into the shading frame.
  const Frame fr = Frame::from_normal_tangent(Vec3{0, 1, 1}, Vec3{1, 0, 0});
  const BSDF bsdf(m, fr);
  const Vec3 wo_l = dir(20, 30), wi_l = dir(40, 100);
  const Vec3 wo = fr.to_world(wo_l), wi = fr.to_world(wi_l) * 3.f;  // unnormalised input
  EXPECT_NEAR(bsdf.f(wo, wi)[0], m.f(wo_l, wi_l)[0], 1e-6);
  EXPECT_NEAR(bsdf.pdf(wo, wi), m.pdf(wo_l, wi_l), 1e-6);
  const auto s = bsdf.sample(wo, 0.2f, 0.3f, 0.4f);
  ASSERT_TRUE(s);
  EXPECT_GT(dot(s->wi, fr.n), 0);
  // Below the tilted surface in world space gives 0.
  EXPECT_TRUE(bsdf.f(wo, -fr.n).is_black());
}

// A user's model through the extension point: Lambert again, written outside the library.
class UserLambert final : public CustomBxDF {
 public:
  BxDFFlags flags() const override { return BxDFFlags::DiffuseReflection; }
  Color f(const Vec3& wo, const Vec3& wi, TransportMode) const override {
    return wo.z * wi.z > 0 ? Color(0.25f) : Color{};
  }
  Float pdf(const Vec3& wo, const Vec3& wi, TransportMode) const override {
    return wo.z * wi.z > 0 ? std::abs(wi.z) * kInvPi : 0;
  }
  std::optional<BSDFSample> sample(const Vec3& wo, Float, Float u1, Float u2, TransportMode) const override {
    Vec3 wi = square_to_cosine_hemisphere(u1, u2);
    if (wo.z == 0 || wi.z == 0) return std::nullopt;
    if (wo.z < 0) wi.z = -wi.z;
    return BSDFSample{wi, Color(0.25f * kPi), std::abs(wi.z) * kInvPi, false, Lobe::Reflection, 1};
  }
  std::string name() const override { return "user-lambert"; }
};

TEST(Models, UserModelGoesWhereBuiltInsGo) {
  const BxDF m = make_user_bxdf<UserLambert>();
  EXPECT_EQ(m.name(), "user-lambert");
  EXPECT_FLOAT_EQ(m.f(dir(10, 0), dir(20, 0))[1], 0.25f);
  const BSDF bsdf(m, Frame{});
  EXPECT_TRUE(bsdf.sample(dir(10, 0), 0.5f, 0.5f, 0.5f).has_value());
  EXPECT_FALSE(m.exact_albedo(dir(10, 0), TransportMode::Radiance).has_value());
}

// Oren & Nayar 1994's full model ("Generalization of Lambert's Reflectance Model",
// SIGGRAPH '94, eqs. 26–29 for the direct term L1 with its coefficients C1, C2, C3, and
// eq. 30's companion interreflection term L2), written here in the paper's angles
// (θ, φ, α = max(θi, θr), β = min(θi, θr), σ in radians), radiance over E0 cos θi.
double oren_nayar_full_paper(double ti, double pi_, double tr, double pr, double sigma, double rho) {
  const double s2 = sigma * sigma, a = std::max(ti, tr), b = std::min(ti, tr), c = std::cos(pr - pi_);
  const double C1 = 1 - 0.5 * s2 / (s2 + 0.33);
  const double C2 = c >= 0 ? 0.45 * s2 / (s2 + 0.09) * std::sin(a)
                           : 0.45 * s2 / (s2 + 0.09) * (std::sin(a) - std::pow(2 * b / kPiD, 3));
  const double C3 = 0.125 * s2 / (s2 + 0.09) * std::pow(4 * a * b / (kPiD * kPiD), 2);
  const double L1 = rho / kPiD * (C1 + c * C2 * std::tan(b) + (1 - std::abs(c)) * C3 * std::tan((a + b) / 2));
  const double L2 = 0.17 * rho * rho / kPiD * s2 / (s2 + 0.13) * (1 - c * std::pow(2 * b / kPiD, 2));
  return L1 + L2;
}

// gonio's full model against the paper's formula written above, in particular where the
// C3 term carries weight: azimuths 90° apart (cos Δφ = 0 leaves C1, C3 and L2) towards
// grazing, where tan((α + β)/2) is large. Also Δφ = 0 and 180° (C2's two branches).
TEST(Models, OrenNayarFullModelIsThePapersEquations) {
  struct Pair { double ti, tr, dphi; };
  const Pair pairs[] = {{50, 70, 90}, {80, 85, 90}, {20, 60, 90}, {75, 40, 90}, {60, 30, 45},
                        {30, 60, 0},  {40, 40, 180}, {10, 70, 135}, {85, 80, 270}};
  for (const double sigma_deg : {10.0, 30.0, 60.0}) {
    const double sigma = sigma_deg * kPiD / 180;
    const OrenNayarBxDF m{Color(0.3f, 0.6f, 0.9f), Float(sigma), true};
    for (const Pair& p : pairs) {
      const Vec3 wi = dir(float(p.ti), 20), wo = dir(float(p.tr), float(20 + p.dphi));
      for (int c = 0; c < 3; ++c) {
        const double rho = 0.3 * (c + 1);
        const double want = oren_nayar_full_paper(p.ti * kPiD / 180, 20 * kPiD / 180, p.tr * kPiD / 180,
                                                  (20 + p.dphi) * kPiD / 180, sigma, rho);
        EXPECT_NEAR(m.f(wo, wi)[c], want, 2e-4 * want)
            << "sigma " << sigma_deg << ", theta_i " << p.ti << ", theta_r " << p.tr << ", dphi " << p.dphi;
      }
    }
  }
}

}  // namespace
}  // namespace gonio
