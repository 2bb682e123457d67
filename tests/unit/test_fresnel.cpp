// Fresnel functions against independently derived values: closed forms (F0, Brewster,
// critical angle), the published figures of REFERENCES.md, and a separate Python
// implementation with different formulas (tests/reference/fresnel_reference.py).

#include <gtest/gtest.h>

#include <cmath>
#include <complex>

#include "../test_common.h"
#include "gonio/bxdf/conductor.h"
#include "gonio/bxdf/dielectric.h"
#include "gonio/fresnel.h"

namespace gonio {
namespace {


struct DielectricCase {
  double eta, theta, rs, rp;
};
// From tests/reference/fresnel_reference.py (angle form of the Fresnel equations).
constexpr DielectricCase kDielectric[] = {
    {1.5, 10, 0.041659486668, 0.038371483361},  {1.5, 30, 0.057796105403, 0.025249146548},
    {1.5, 45, 0.092013363046, 0.008466458979},  {1.5, 60, 0.176571488083, 0.001801937522},
    {1.5, 75, 0.399356027000, 0.106765098980},  {1.5, 80, 0.538594905750, 0.236813803633},
    {1.5, 89, 0.939472161295, 0.868897738265},  {1.333, 30, 0.030933990890, 0.011938940837},
    {1.333, 60, 0.115067934113, 0.004313904238}, {1.333, 89, 0.923858122363, 0.868694685126},
    {1 / 1.5, 10, 0.043887869961, 0.036278048349}, {1 / 1.5, 30, 0.105772791145, 0.004607543446},
    {1 / 1.5, 45, 1, 1},                        {2.4, 45, 0.279508818168, 0.078125179434},
    {2.4, 75, 0.622873350843, 0.036674518995},  {2.4, 89, 0.968509634558, 0.831579400501},
};

TEST(Fresnel, DielectricMatchesIndependentImplementation) {
  for (const auto& c : kDielectric) {
    const double ci = std::cos(c.theta * kDeg);
    const auto t = fresnel_dielectric_terms(ci, c.eta);
    EXPECT_NEAR(t.rs, c.rs, 1e-10) << "eta " << c.eta << " theta " << c.theta;
    EXPECT_NEAR(t.rp, c.rp, 1e-10) << "eta " << c.eta << " theta " << c.theta;
    EXPECT_NEAR(fresnel_dielectric(ci, c.eta), (c.rs + c.rp) / 2, 1e-10);
    // Single precision, as the models use it, agrees to 1e-5.
    EXPECT_NEAR(fresnel_dielectric(float(ci), float(c.eta)), (c.rs + c.rp) / 2, 1e-5);
  }
}

TEST(Fresnel, ReferenceFiguresForGlass) {
  // REFERENCES.md: glass η = 1.5 from outside.
  const auto t45 = fresnel_dielectric_terms(std::cos(45 * kDeg), 1.5);
  EXPECT_NEAR(t45.rs, 0.092013, 1e-6);
  EXPECT_NEAR(t45.rp, 0.008466, 1e-6);
  EXPECT_NEAR(t45.r(), 0.050240, 1e-6);
  EXPECT_NEAR(std::acos(t45.cos_t) / kDeg, 28.1255, 1e-4);
  EXPECT_NEAR(fresnel_dielectric(std::cos(60 * kDeg), 1.5), 0.089187, 1e-6);
  EXPECT_NEAR(fresnel_dielectric(std::cos(80 * kDeg), 1.5), 0.387704, 1e-6);
}

TEST(Fresnel, NormalIncidenceIsF0) {
  for (double eta : {1.0001, 1.33, 1.5, 2.4, 0.5, 1 / 1.5}) {
    const double f0 = ((eta - 1) / (eta + 1)) * ((eta - 1) / (eta + 1));
    EXPECT_NEAR(fresnel_dielectric(1.0, eta), f0, 1e-14) << eta;
    EXPECT_NEAR(fresnel_f0(eta), f0, 1e-14) << eta;
    // From the other side the relative index is 1/η, F0 is the same.
    EXPECT_NEAR(fresnel_dielectric(-1.0, eta), f0, 1e-14) << eta;
  }
}

TEST(Fresnel, BrewsterAngleHasNoPReflection) {
  for (double eta : {1.33, 1.5, 2.4}) {
    const double brewster = std::atan(eta);  // tan θB = η
    const auto t = fresnel_dielectric_terms(std::cos(brewster), eta);
    EXPECT_LT(t.rp, 1e-20) << eta;
    EXPECT_GT(t.rs, 0.01) << eta;
    // From inside, Brewster's angle is atan(1/η).
    EXPECT_LT(fresnel_dielectric_terms(-std::cos(std::atan(1 / eta)), eta).rp, 1e-20);
  }
}

TEST(Fresnel, TotalInternalReflectionBeyondTheCriticalAngle) {
  const double eta = 1.5;
  const double critical = std::asin(1 / eta);
  EXPECT_NEAR(critical / kDeg, 41.8103, 1e-4);  // REFERENCES.md
  // Light inside the glass (cos_i < 0 in the outside-normal convention).
  for (double d : {1e-6, 0.01, 0.3}) {
    const auto beyond = fresnel_dielectric_terms(-std::cos(critical + d), eta);
    EXPECT_TRUE(beyond.tir);
    EXPECT_EQ(beyond.r(), 1.0);
    const auto before = fresnel_dielectric_terms(-std::cos(critical - d), eta);
    EXPECT_FALSE(before.tir);
    EXPECT_LT(before.r(), 1.0);
  }
  // Exactly at the critical angle (as close as floating point gets): finite, in [0, 1].
  for (float c : {std::cos(float(critical)), std::nextafter(std::cos(float(critical)), 0.f),
                  std::nextafter(std::cos(float(critical)), 1.f)}) {
    const float r = fresnel_dielectric(-c, 1.5f);
    EXPECT_TRUE(std::isfinite(r));
    EXPECT_GE(r, 0.f);
    EXPECT_LE(r, 1.f);
  }
  // The SPEC rule: sin²θt = 1 exactly is total. These give sin²θt = 1 in exact arithmetic.
  EXPECT_TRUE(fresnel_dielectric_terms(0.0, 1.0).tir);
  EXPECT_TRUE(fresnel_dielectric_terms(0.0, 0.5).tir);
  EXPECT_EQ(fresnel_dielectric(0.0f, 1.0f), 1.0f);
}

TEST(Fresnel, StokesRelationOutsideEqualsInsideAtTheRefractedAngle) {
  // R(θi, η) = R(θt, 1/η): Fresnel reflectance is the same seen from both sides of a ray.
  for (double th = 0; th < 89.5; th += 7.5) {
    const auto out = fresnel_dielectric_terms(std::cos(th * kDeg), 1.5);
    const auto in = fresnel_dielectric_terms(-out.cos_t, 1.5);
    EXPECT_NEAR(out.rs, in.rs, 1e-12);
    EXPECT_NEAR(out.rp, in.rp, 1e-12);
  }
}

TEST(Fresnel, FiniteEverywhereIncludingGrazingAndEtaOne) {
  for (double eta : {1e-3, 0.5, 1.0, 1.5, 1e3}) {
    for (double c : {-1.0, -0.5, -1e-30, 0.0, 1e-30, 0.5, 1.0, 1.5, -1.5}) {
      const auto t = fresnel_dielectric_terms(c, eta);
      EXPECT_TRUE(std::isfinite(t.rs) && std::isfinite(t.rp) && std::isfinite(t.cos_t));
      EXPECT_GE(t.r(), 0);
      EXPECT_LE(t.r(), 1);
      const float rf = fresnel_dielectric(float(c), float(eta));
      EXPECT_TRUE(std::isfinite(rf) && rf >= 0 && rf <= 1);
      for (double k : {0.0, 1e-3, 3.0}) {
        const auto ct = fresnel_conductor_terms(c, eta, k);
        EXPECT_TRUE(std::isfinite(ct.rs) && std::isfinite(ct.rp));
        EXPECT_GE(ct.r(), 0);
        EXPECT_LE(ct.r(), 1);
      }
    }
  }
  // η = 1: no interface, nothing reflects (away from exact grazing).
  EXPECT_NEAR(fresnel_dielectric(0.3, 1.0), 0.0, 1e-15);
  EXPECT_EQ(fresnel_conductor(0.0, 1.0, 0.0), 0.0);
}

struct ConductorCase {
  double n, k, theta, rs, rp;
};
constexpr ConductorCase kConductor[] = {
    // From tests/reference/fresnel_reference.py (real a², b² form).
    {0.3504, 2.7141, 0, 0.847485053505, 0.847485053505},
    {0.3504, 2.7141, 30, 0.868471269842, 0.825336120613},
    {0.3504, 2.7141, 60, 0.924086654269, 0.762594137947},
    {0.3504, 2.7141, 80, 0.973297665113, 0.807775514119},
    {0.3504, 2.7141, 89, 0.997288220681, 0.974688273063},
    {0.1678, 3.1378, 60, 0.970672340019, 0.900127950027},
    {0.618, 5.4694, 80, 0.986578961982, 0.792907438602},
    {0.2166, 3.6377, 89, 0.998978905391, 0.984575319852},
};

TEST(Fresnel, ConductorMatchesIndependentImplementation) {
  for (const auto& c : kConductor) {
    const double ci = std::cos(c.theta * kDeg);
    const auto t = fresnel_conductor_terms(ci, c.n, c.k);
    EXPECT_NEAR(t.rs, c.rs, 1e-10) << c.n << " " << c.theta;
    EXPECT_NEAR(t.rp, c.rp, 1e-10) << c.n << " " << c.theta;
    EXPECT_NEAR(fresnel_conductor(float(ci), float(c.n), float(c.k)), (c.rs + c.rp) / 2, 1e-5);
  }
}

// The models' hot paths use the same Fresnel (one implementation, fresnel.h): the smooth
// dielectric's reflection probability, the cancellation-free transmittance the rough
// dielectric uses, and the conductor's four-lane SIMD form, all against the reference.
TEST(Fresnel, ModelHotPathsMatchIndependentImplementation) {
  for (const auto& c : kDielectric) {
    const double ci = std::cos(c.theta * kDeg), r = (c.rs + c.rp) / 2;
    const float s = float(std::sqrt(1 - ci * ci));
    const auto smp = DielectricBxDF{float(c.eta)}.sample({s, 0, float(ci)}, 0.f, 0.5f, 0.5f);
    ASSERT_TRUE(smp);
    EXPECT_NEAR(smp->pdf, r, 1e-5) << "eta " << c.eta << " theta " << c.theta;  // P(reflection) = F
    if (r < 1) {
      // cos θt by Snell's law, both cosines scaled by 3 (the form is homogeneous).
      const double ct = std::sqrt(1 - (1 - ci * ci) / (c.eta * c.eta));
      EXPECT_NEAR(fresnel_dielectric_parts(3 * ci, 3 * ct, c.eta).t(), 1 - r, 1e-12);
      EXPECT_NEAR(fresnel_dielectric_parts(3 * ci, 3 * ct, c.eta).r(), r, 1e-12);
    }
  }
  for (const auto& c : kConductor) {
    const double ci = std::cos(c.theta * kDeg);
    ConductorFresnel fr;
    fr.eta = Color(float(c.n));
    fr.k = Color(float(c.k));
    const Color f = fr(float(ci));
    for (int i = 0; i < Color::size(); ++i) EXPECT_NEAR(f[i], (c.rs + c.rp) / 2, 1e-5) << c.n << " " << c.theta;
  }
}

TEST(Fresnel, ConductorWithZeroExtinctionIsTheDielectric) {
  for (double eta : {1.2, 1.5, 2.4})
    for (double th = 0; th < 90; th += 5) {
      const double c = std::cos(th * kDeg);
      const auto a = fresnel_conductor_terms(c, eta, 0.0);
      const auto b = fresnel_dielectric_terms(c, eta);
      EXPECT_NEAR(a.rs, b.rs, 1e-12);
      EXPECT_NEAR(a.rp, b.rp, 1e-12);
    }
}

TEST(Fresnel, ConductorAgreesWithStdComplex) {
  // A third route: the complex equations evaluated with std::complex<long double>.
  using C = std::complex<long double>;
  for (double th : {0.0, 20.0, 50.0, 70.0, 85.0}) {
    const long double ci = std::cos(th * kDeg), s2 = 1 - ci * ci;
    const C eta(0.35, 2.71);
    const C w = std::sqrt(eta * eta - s2);
    const long double rs = std::norm((ci - w) / (ci + w));
    const long double rp = std::norm((eta * eta * ci - w) / (eta * eta * ci + w));
    const auto t = fresnel_conductor_terms(double(ci), 0.35, 2.71);
    EXPECT_NEAR(t.rs, double(rs), 1e-12);
    EXPECT_NEAR(t.rp, double(rp), 1e-12);
  }
}

TEST(Fresnel, SchlickApproximation) {
  // Lecture eq. 28 at a few angles, F0 of glass.
  const double f0 = 0.04;
  for (double c : {0.0, 0.25, 0.5, 1.0})
    EXPECT_NEAR(fresnel_schlick(f0, c), f0 + (1 - f0) * std::pow(1 - c, 5), 1e-15);
  // SPEC §3: for eta < 1 the refracted cosine enters; 1 under total internal reflection.
  const double eta = 1 / 1.5, ci = std::cos(30 * kDeg);
  const double ct = std::sqrt(1 - (1 - ci * ci) / (eta * eta));
  EXPECT_NEAR(fresnel_schlick_dielectric(ci, eta), f0 + (1 - f0) * std::pow(1 - ct, 5), 1e-12);
  EXPECT_EQ(fresnel_schlick_dielectric(std::cos(60 * kDeg), eta), 1.0);
  // Conductor F0 = ((n−1)² + k²)/((n+1)² + k²) equals the exact value at normal incidence.
  EXPECT_NEAR(fresnel_f0(0.3504, 2.7141), 0.847485053505, 1e-10);
}

TEST(Fresnel, ReflectionDirection) {
  // Lecture §5.2 with I = −wo: R = I − 2(I·N)N, i.e. θr = θi and φr = φi ± π.
  const Vec3 n = normalize(Vec3{0.2f, -0.3f, 1});
  const Vec3 wo = normalize(Vec3{0.5f, 0.1f, 0.7f});
  const Vec3 r = reflect(wo, n);
  EXPECT_NEAR(length(r), 1, 1e-6);
  EXPECT_NEAR(dot(r, n), dot(wo, n), 1e-6);
  EXPECT_NEAR(dot(cross(n, wo), r), 0, 1e-6);  // in the plane of incidence
  EXPECT_NEAR(length(r + wo - n * (2 * dot(wo, n))), 0, 1e-6);
}

TEST(Fresnel, RefractionObeysSnellsLaw) {
  const Vec3 n{0, 0, 1};
  for (float eta : {1.5f, 1.333f, 0.8f, 1.0f})
    for (float th = 0; th < 89.f; th += 11.f) {
      const float t = th * float(kDeg);
      const Vec3 wi{std::sin(t) * std::cos(0.7f), std::sin(t) * std::sin(0.7f), std::cos(t)};
      const auto r = refract(wi, n, eta);
      const double sin_t_expected = std::sin(t) / eta;
      if (sin_t_expected >= 1) {
        EXPECT_FALSE(r) << eta << " " << th;
        continue;
      }
      ASSERT_TRUE(r) << eta << " " << th;
      EXPECT_NEAR(length(r->wt), 1, 1e-6);
      EXPECT_LT(r->wt.z, 0);  // on the far side
      // n_i sin θi = n_t sin θt
      EXPECT_NEAR(std::sin(t), eta * length(cross(r->wt, n)), 2e-6);
      // coplanar with wi and n, on the opposite side of n in azimuth (φt = φi ± π)
      EXPECT_NEAR(dot(cross(n, wi), r->wt), 0, 1e-6);
      EXPECT_LE(r->wt.x * wi.x + r->wt.y * wi.y, 1e-7);
      // and reversible: refracting back gives wi
      const auto back = refract(r->wt, n, eta);
      ASSERT_TRUE(back);
      EXPECT_NEAR(length(back->wt - wi), 0, 4e-6);
      EXPECT_FLOAT_EQ(back->eta, 1 / eta);
    }
}

}  // namespace
}  // namespace gonio
