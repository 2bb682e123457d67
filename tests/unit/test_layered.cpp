// The layered BSDF (issue 34, item 6) against values computed here, independently of its
// walk: the white furnace of a non-absorbing stack (albedo 1), a black base that leaves
// the top's own reflection (Fresnel written below; a rough top's f), the mirror base's
// geometric series R = F0 + (1 − F0)² e^{−2τ} / (1 − F0 e^{−2τ}), agreement with the
// closed-form `plastic` within the Monte Carlo error, exact reciprocity; through a
// transmitting bottom, a stack with an invisible interface equal to the other alone, the
// white furnace from both sides, a glass slab's incoherent sums; the parser's refusals. Monte Carlo tolerances are 4.5 standard errors estimated from the same samples.

#include <gtest/gtest.h>

#include <cmath>
#include <complex>
#include <string>
#include <vector>

#include "gonio/bxdf.h"
#include "gonio/error.h"
#include "gonio/material.h"
#include "gonio/rng.h"
#include "gonio/spectral_material.h"
#include "gonio/validate.h"
#include "test_scale.h"

namespace gonio {
namespace {

// Unpolarised Fresnel reflectance of a dielectric (Hecht, Optics, eqs. 4.42–4.43), written
// here in double from the amplitude coefficients, for light from outside (n = 1) at cos θ = c.
double layered_test_fresnel(double c, double eta) {
  const double s2 = (1 - c * c) / (eta * eta);
  if (s2 >= 1) return 1;
  const double ct = std::sqrt(1 - s2);
  const double rs = (c - eta * ct) / (c + eta * ct);
  const double rp = (eta * c - ct) / (eta * c + ct);
  return (rs * rs + rp * rp) / 2;
}

Vec3 layered_test_dir(double theta_deg, double phi_deg) {
  const double t = theta_deg * kPiD / 180, p = phi_deg * kPiD / 180;
  return {Float(std::sin(t) * std::cos(p)), Float(std::sin(t) * std::sin(p)), Float(std::cos(t))};
}

struct LayeredMean {
  double mean = 0, se = 0;
};
// Mean of sample weights (channel 0): the directional albedo and its standard error.
LayeredMean layered_albedo(const BxDF& m, const Vec3& wo, int n, std::uint64_t seed, int channel = 0) {
  Pcg32 rng(seed);
  double s = 0, s2 = 0;
  for (int i = 0; i < n; ++i) {
    const auto smp = m.sample(wo, rng.next_float(), rng.next_float(), rng.next_float(), TransportMode::Importance);
    const double w = smp ? double(smp->weight[channel]) : 0.0;
    s += w;
    s2 += w * w;
  }
  const double mean = s / n;
  return {mean, std::sqrt(std::max(0.0, s2 / n - mean * mean) / n)};
}

// Over the pairs jittered within ±1° of a region (θo, φo, θi, φi in degrees) — n distinct
// pairs, each an independent estimate of f (its own seed) — the mean of f − want and its
// standard error, and the mean of want.
struct LayeredRegionError {
  double mean = 0, se = 0, want = 0;
};
template <typename Want>
LayeredRegionError layered_region_error(const BxDF& m, const double (&region)[4], int n, Pcg32& rng, Want want_of) {
  double s = 0, s2 = 0, ref = 0;
  for (int i = 0; i < n; ++i) {
    const auto j = [&] { return 2 * rng.next_double() - 1; };
    const Vec3 wo = layered_test_dir(std::abs(region[0] + j()), region[1] + j());
    const Vec3 wi = layered_test_dir(region[2] + j(), region[3] + j());
    const double want = want_of(wo, wi), d = m.f(wo, wi)[0] - want;
    s += d;
    s2 += d * d;
    ref += want;
  }
  const double mean = s / n;
  return {mean, std::sqrt(std::max(0.0, s2 / n - mean * mean) / n), ref / n};
}

// A non-absorbing stack over a white Lambertian base returns every joule: albedo 1 at every
// angle (the walk's depth cap loses < 1e-4), smooth or rough top, with or without a
// scattering medium.
TEST(Layered, WhiteFurnaceIsOne) {
  const char* stacks[] = {
      R"({"type":"layered","top":{"type":"dielectric","eta":1.5},"bottom":{"type":"diffuse","reflectance":1},"thickness":0})",
      R"({"type":"layered","top":{"type":"dielectric","eta":1.5},"bottom":{"type":"diffuse","reflectance":1},"thickness":0.5,"albedo":1,"g":0.3})",
      R"({"type":"layered","top":{"type":"roughdielectric","eta":1.5,"alpha":0.3,"multiscatter":true},"bottom":{"type":"diffuse","reflectance":1},"thickness":0})",
      // Two delta interfaces around a white medium: light scattered last in the medium
      // leaves only by delta bounces (the walk's legs to the exit, delta_legs_to_exit).
      R"({"type":"layered","top":{"type":"dielectric","eta":1.5},"bottom":{"type":"mirror"},"thickness":0.5,"albedo":1,"g":0.3})",
  };
  const int n = int(test::scaled(20000));
  for (const char* desc : stacks) {
    const BxDF m = parse_material(desc);
    for (double th : {0.0, 30.0, 60.0, 80.0}) {
      const LayeredMean a = layered_albedo(m, layered_test_dir(th, 20), n, 3);
      // The rough top's energy compensation (Kulla & Conty) is exact only to its tables' ~0.5 %.
      const double slack = std::string(desc).find("rough") != std::string::npos ? 6e-3 : 1e-4;
      EXPECT_NEAR(a.mean, 1.0, 4.5 * a.se + slack) << desc << " at " << th << " deg";
    }
  }
}

// A black base: only the top's reflection is left. Smooth top: the delta lobe's weight is F
// (Fresnel above), nothing else. Rough top: f equals the top's own f at every pair.
TEST(Layered, BlackBaseLeavesTheTopsReflection) {
  const BxDF smooth = parse_material(
      R"({"type":"layered","top":{"type":"dielectric","eta":1.7},"bottom":{"type":"diffuse","reflectance":0},"thickness":0.2})");
  for (double th : {0.0, 40.0, 75.0, 89.0}) {
    const Vec3 wo = layered_test_dir(th, 0);
    const double F = layered_test_fresnel(std::cos(th * kPiD / 180), 1.7);
    // u_lobe = 0 chooses the delta lobe: weight × probability is the lobe's reflectance.
    const auto d = smooth.sample(wo, 0, 0.5f, 0.5f);
    ASSERT_TRUE(d && d->delta) << th;
    EXPECT_NEAR(d->weight[0] * d->pdf, F, 1e-5 * F) << th;
    EXPECT_NEAR(d->wi.x, -wo.x, 1e-6);
    // Everything else carries nothing: f = 0 at every pair.
    Pcg32 r(5);
    for (int i = 0; i < 100; ++i) {
      const auto s = smooth.sample(wo, 0.999f, r.next_float(), r.next_float());
      if (s) {
        EXPECT_EQ(s->weight[0], 0) << th;
      }
    }
  }
  const BxDF rough = parse_material(
      R"({"type":"layered","top":{"type":"roughdielectric","eta":1.5,"alpha":0.2},"bottom":{"type":"diffuse","reflectance":0}})");
  const BxDF top = parse_material(R"({"type":"roughdielectric","eta":1.5,"alpha":0.2})");
  Pcg32 rng(9);
  for (int i = 0; i < 200; ++i) {
    const Vec3 wo = layered_test_dir(85 * rng.next_double(), 360 * rng.next_double());
    const Vec3 wi = layered_test_dir(85 * rng.next_double(), 360 * rng.next_double());
    const double want = 0.5 * (double(top.f(wo, wi)[0]) + double(top.f(wi, wo)[0]));
    EXPECT_NEAR(rough.f(wo, wi)[0], want, 1e-5 * want + 1e-9);
  }
}

// Over a mirror, at normal incidence, a medium of optical depth τ that only absorbs: the
// geometric series of the bounces, R = F0 + (1 − F0)² e^{−2τ} / (1 − F0 e^{−2τ}), the
// whole reflection in the delta lobe (f = 0). At 50° the same with τ/μ' (μ' the refracted
// cosine by Snell's law) and F(50°).
TEST(Layered, MirrorBaseIsTheGeometricSeries) {
  const double eta = 1.5;
  const int n = int(test::scaled(4000));
  for (double tau : {0.0, 0.1, 0.5, 2.0}) {
    for (double th : {0.0, 50.0}) {
      const std::string desc = R"({"type":"layered","top":{"type":"dielectric","eta":1.5},"bottom":{"type":"mirror"},"thickness":)" +
                               std::to_string(tau) + "}";
      const BxDF m = parse_material(desc);
      const double c = std::cos(th * kPiD / 180);
      const double F = layered_test_fresnel(c, eta);
      const double mu_in = std::sqrt(1 - (1 - c * c) / (eta * eta));
      const double T = std::exp(-2 * tau / mu_in);
      const double want = F + (1 - F) * (1 - F) * T / (1 - F * T);
      const LayeredMean a = layered_albedo(m, layered_test_dir(th, 10), n, 17);
      EXPECT_NEAR(a.mean, want, 4.5 * a.se + 1e-5) << "tau " << tau << " theta " << th;
      EXPECT_EQ(m.f(layered_test_dir(th, 10), layered_test_dir(th + 1, 190))[0], 0);
    }
  }
}

// A smooth dielectric over a Lambertian base, no medium, is what `plastic` computes in
// closed form: f agrees within the walk's Monte Carlo error. Each region (θo, θi within
// ±1°, azimuths within ±1°) gives n distinct pairs, each an independent estimate (its own
// seed); the mean of layered f − plastic f over them must be 0 within 4.5 standard errors.
TEST(Layered, AgreesWithPlastic) {
  const BxDF layered = parse_material(
      R"({"type":"layered","top":{"type":"dielectric","eta":1.5},"bottom":{"type":"diffuse","reflectance":0.6},"thickness":0})");
  const BxDF plastic = parse_material(R"({"type":"plastic","eta":1.5,"reflectance":0.6})");
  const int n = int(test::scaled(3000));
  const double pairs[][4] = {{0, 0, 30, 180}, {45, 0, 45, 180}, {70, 30, 20, 100}, {85, 0, 60, 90}};
  Pcg32 rng(19);
  for (const auto& p : pairs) {
    const auto e = layered_region_error(layered, p, n, rng, [&](const Vec3& wo, const Vec3& wi) { return plastic.f(wo, wi)[0]; });
    EXPECT_NEAR(e.mean, 0.0, 4.5 * e.se + 1e-4 * e.want) << p[0] << " " << p[2] << " (plastic " << e.want << ")";
  }
  for (double th : {0.0, 60.0, 85.0}) {
    const Vec3 wo = layered_test_dir(th, 0);
    const LayeredMean a = layered_albedo(layered, wo, int(test::scaled(20000)), 23);
    EXPECT_NEAR(a.mean, plastic.exact_albedo(wo, TransportMode::Radiance)->reflectance[0], 4.5 * a.se + 1e-4) << th;
  }
}

// f(wo, wi) = f(wi, wo) bit for bit (the symmetric estimator), in both modes, and f
// does not depend on the mode (the stack only reflects).
TEST(Layered, ReciprocityIsExact) {
  const char* stacks[] = {
      R"({"type":"layered","top":{"type":"roughdielectric","eta":1.4,"alpha":0.4},"bottom":{"type":"roughconductor","alpha":0.2,"eta":[0.2,0.9,1.1],"k":[3.9,2.4,2.2]},"thickness":0.3,"albedo":[0.9,0.5,0.2],"g":0.5})",
      R"({"type":"layered","top":{"type":"dielectric","eta":1.33},"bottom":{"type":"orennayar","sigma":20},"thickness":1,"albedo":0.8,"g":-0.3})",
  };
  for (const char* desc : stacks) {
    const BxDF m = parse_material(desc);
    Pcg32 rng(31);
    for (int i = 0; i < 300; ++i) {
      const Vec3 wo = layered_test_dir(89 * rng.next_double(), 360 * rng.next_double());
      const Vec3 wi = layered_test_dir(89 * rng.next_double(), 360 * rng.next_double());
      const Color a = m.f(wo, wi, TransportMode::Radiance), b = m.f(wi, wo, TransportMode::Radiance);
      const Color c = m.f(wi, wo, TransportMode::Importance);
      for (int k = 0; k < 3; ++k) {
        EXPECT_EQ(a[k], b[k]) << desc;
        EXPECT_EQ(a[k], c[k]) << desc;
        EXPECT_TRUE(std::isfinite(a[k]) && a[k] >= 0);
      }
    }
  }
}

// Spectral mode: the same stack at 4 wavelengths keeps a white furnace.
TEST(Layered, SpectralWhiteFurnace) {
  const MaterialWithSpectra mat = parse_material_with_spectra(
      R"({"type":"layered","top":{"type":"dielectric","eta":1.5},"bottom":{"type":"diffuse","reflectance":1},"thickness":0.2,"albedo":1})");
  SampledWavelengths w = SampledWavelengths::sample_visible(0.37f);
  SpectralScratch scratch;
  const SpectralBxDF s = to_spectral(mat.bxdf, mat.spectra, w, scratch);
  ASSERT_EQ(s.name(), "layered");
  Pcg32 rng(41);
  const int n = int(test::scaled(20000));
  double sum = 0, sum2 = 0;
  for (int i = 0; i < n; ++i) {
    const auto smp = s.sample(layered_test_dir(45, 0), rng.next_float(), rng.next_float(), rng.next_float());
    const double v = smp ? double(smp->weight.average()) : 0.0;
    sum += v;
    sum2 += v * v;
  }
  const double mean = sum / n, se = std::sqrt(std::max(0.0, sum2 / n - mean * mean) / n);
  EXPECT_NEAR(mean, 1.0, 4.5 * se + 2e-3);  // the upsampled grey 1 is 1 to ~1e-3
}

// Single scattering in a slab, derived here: a beam entering along −wi through an
// index-matched top (η = 1: no refraction, no reflection) is attenuated to e^{−t/μi} at
// optical depth t, scatters there with albedo ω and phase p(cos Θ) (Henyey–Greenstein,
// per steradian, Θ between the directions of travel −wi and wo), and leaves attenuated by
// e^{−t/μo}; with dt/μo along the viewing ray and f = L / (E μi),
//   f_ss = ω p(−wi·wo) (1 − e^{−τ (1/μo + 1/μi)}) / (μo + μi)
// (the single-scattering term of a plane-parallel slab; Chandrasekhar 1960, Radiative
// Transfer, §I.14). With a black bottom and max_depth 1 the walk keeps exactly that
// order, so the mean of (f − f_ss) over nearby pairs (each its own seed) is 0.
TEST(Layered, SingleScatteringIsTheSlabsClosedForm) {
  const double omega = 0.8, tau = 0.3, g = 0.6;
  const BxDF m = parse_material(
      R"({"type":"layered","top":{"type":"dielectric","eta":1},"bottom":{"type":"diffuse","reflectance":0},"thickness":0.3,"albedo":0.8,"g":0.6,"max_depth":1})");
  const auto hg = [&](double c) { return (1 - g * g) / (4 * kPiD * std::pow(1 + g * g - 2 * g * c, 1.5)); };
  const int n = int(test::scaled(4000));
  const double pairs[][4] = {{0, 0, 30, 180}, {40, 0, 40, 180}, {60, 0, 60, 0}, {75, 30, 20, 100}};
  Pcg32 rng(43);
  const auto single_scattering = [&](const Vec3& wo, const Vec3& wi) {
    const double mo = wo.z, mi = wi.z;
    const double cos_travel = -(double(wi.x) * wo.x + double(wi.y) * wo.y + double(wi.z) * wo.z);
    return omega * hg(cos_travel) * -std::expm1(-tau * (1 / mo + 1 / mi)) / (mo + mi);
  };
  for (const auto& p : pairs) {
    const auto e = layered_region_error(m, p, n, rng, single_scattering);
    EXPECT_NEAR(e.mean, 0.0, 4.5 * e.se + 1e-6) << p[0] << " " << p[2] << " (f_ss " << e.want << ")";
  }
}

// A thin dielectric sheet as the top (SPEC §2): per polarization r from Fresnel's amplitudes
// (above), the sheet reflects 2r/(1 + r) (Stokes' series; thindielectric.h), written here
// in double, and light crosses it without bending.
double layered_test_sheet(double c, double eta) {
  const double s2 = (1 - c * c) / (eta * eta);
  if (s2 >= 1) return 1;
  const double ct = std::sqrt(1 - s2);
  const double rs = (c - eta * ct) / (c + eta * ct), rp = (eta * c - ct) / (eta * c + ct);
  const double Rs = rs * rs, Rp = rp * rp;
  return (2 * Rs / (1 + Rs) + 2 * Rp / (1 + Rp)) / 2;
}

// Over a black base the sheet's delta lobe carries its R and nothing else; over a mirror
// through an absorbing medium the chain is R + (1 − R)² T / (1 − R T) with T = e^{−2τ/cos θ}
// — the cosine outside, since the sheet does not refract (the walk sums unpolarized
// energy: R is the average of the polarizations); over a white Lambertian base with a
// non-absorbing medium, albedo 1.
TEST(Layered, ThinSheetTop) {
  const double eta = 1.6;
  const BxDF black = parse_material(
      R"({"type":"layered","top":{"type":"thindielectric","eta":1.6},"bottom":{"type":"diffuse","reflectance":0},"thickness":0.2})");
  for (double th : {0.0, 40.0, 75.0, 89.0}) {
    const Vec3 wo = layered_test_dir(th, 30);
    const double R = layered_test_sheet(std::cos(th * kPiD / 180), eta);
    const auto d = black.sample(wo, 0, 0.5f, 0.5f);
    ASSERT_TRUE(d && d->delta) << th;
    EXPECT_NEAR(d->weight[0] * d->pdf, R, 1e-5 * R) << th;
  }
  for (double tau : {0.0, 0.3, 1.0}) {
    const BxDF m = parse_material(
        R"({"type":"layered","top":{"type":"thindielectric","eta":1.6},"bottom":{"type":"mirror"},"thickness":)" +
        std::to_string(tau) + "}");
    for (double th : {0.0, 50.0, 80.0}) {
      const double c = std::cos(th * kPiD / 180), R = layered_test_sheet(c, eta), T = std::exp(-2 * tau / c);
      const double want = R + (1 - R) * (1 - R) * T / (1 - R * T);
      const LayeredMean a = layered_albedo(m, layered_test_dir(th, 10), int(test::scaled(2000)), 29);
      EXPECT_NEAR(a.mean, want, 4.5 * a.se + 1e-5) << "tau " << tau << " theta " << th;
    }
  }
  const BxDF white = parse_material(
      R"({"type":"layered","top":{"type":"thindielectric","eta":1.6},"bottom":{"type":"diffuse","reflectance":1},"thickness":0.5,"albedo":1,"g":-0.4})");
  for (double th : {0.0, 60.0, 85.0}) {
    const LayeredMean a = layered_albedo(white, layered_test_dir(th, 20), int(test::scaled(20000)), 37);
    EXPECT_NEAR(a.mean, 1.0, 4.5 * a.se + 1e-4) << th;
  }
}

// The top's thin film is the top's: at 550 nm and normal incidence, over a black base, the
// delta lobe reflects the quarter-wave MgF2 coating's 1.41 % (the Airy sum, n 1.38, 99.6 nm
// on n 1.5: 0.0141104680243605 from the Python reference, tests/unit/test_thin_film.cpp);
// a sheet under a soap film (n 1.33, 300 nm in air) reflects |r (1 − e^{iδ}) /
// (1 − r² e^{iδ})|², r = (1 − 1.33)/(1 + 1.33), δ = 4π n d / λ, written here.
TEST(Layered, TopFilmIsTheTopsReflection) {
  const auto delta_reflectance = [](const char* desc) {
    const MaterialWithSpectra m = parse_material_with_spectra(desc);
    SampledWavelengths w = SampledWavelengths::single(550);
    SpectralScratch scratch;
    const SpectralBxDF s = to_spectral(m.bxdf, m.spectra, w, scratch);
    const auto d = s.sample({0, 0, 1}, 0, 0.5f, 0.5f);
    return d && d->delta ? double(d->weight[0] * d->pdf) : -1.0;
  };
  EXPECT_NEAR(delta_reflectance(R"({"type":"layered","top":{"type":"dielectric","eta":1.5,"thin_film":{"thickness":99.6,"eta":1.38}},"bottom":{"type":"diffuse","reflectance":0}})"),
              0.0141104680243605, 1e-6);
  const double r = (1 - 1.33) / (1 + 1.33), delta = 4 * kPiD * 1.33 * 300 / 550;
  const std::complex<double> e = std::polar(1.0, delta);
  const double soap = std::norm(r * (1.0 - e) / (1.0 - r * r * e));
  EXPECT_NEAR(delta_reflectance(R"({"type":"layered","top":{"type":"thindielectric","thin_film":{"thickness":300,"eta":1.33}},"bottom":{"type":"diffuse","reflectance":0}})"),
              soap, 1e-6);
}

// The parser: one line naming the field and the value.
// A bottom that transmits: the stack transmits. Where one interface does nothing (index
// 1: no reflection, no bending), the stack is the other interface alone, in both
// directions, both transport modes and across the surface: f equals that material's f
// at every pair (the walk's straight crossing from the entry to the exit, and the
// (n_wo/n_wi)² relating its two ends).
TEST(Layered, TransmittingBottomWithAnInvisibleInterface) {
  const char* pairs[][2] = {
      {R"({"type":"layered","top":{"type":"dielectric","eta":1},"bottom":{"type":"roughdielectric","eta":1.5,"alpha":0.3},"thickness":0})",
       R"({"type":"roughdielectric","eta":1.5,"alpha":0.3})"},
      {R"({"type":"layered","top":{"type":"roughdielectric","eta":1.5,"alpha":0.3},"bottom":{"type":"dielectric","eta":1},"thickness":0})",
       R"({"type":"roughdielectric","eta":1.5,"alpha":0.3})"},
  };
  for (const auto& [stack_desc, alone_desc] : pairs) {
    const BxDF stack = parse_material(stack_desc), alone = parse_material(alone_desc);
    EXPECT_FLOAT_EQ(stack.relative_eta(), 1.5f);
    Pcg32 rng(41);
    int compared = 0;
    for (int i = 0; i < 4000; ++i) {
      const Vec3 wo = square_to_uniform_sphere(rng.next_float(), rng.next_float());
      const Vec3 wi = square_to_uniform_sphere(rng.next_float(), rng.next_float());
      // Within 1e-3 of grazing an index-1 dielectric's float Fresnel is not 0 (cos θt is
      // computed from sin θ, and at cos θ = 3e-5 rounds to 0: F = 1).
      if (std::abs(wo.z) < 1e-3f || std::abs(wi.z) < 1e-3f) continue;
      for (const TransportMode mode : {TransportMode::Radiance, TransportMode::Importance}) {
        const double want = alone.f(wo, wi, mode)[0], got = stack.f(wo, wi, mode)[0];
        EXPECT_NEAR(got, want, 1e-3 * want + 1e-6) << stack_desc << " wo " << wo.z << " wi " << wi.z;
        compared += want > 1e-3;
      }
    }
    EXPECT_GT(compared, 1000);
  }
}

// A lossless stack that transmits keeps every joule: reflectance + transmittance = 1 from
// either side (importance mode: the fractions of the light arriving along wo), with rough
// interfaces (energy-compensated to their tables' ~0.5 % each) and a white medium.
TEST(Layered, TransmittingWhiteFurnaceIsOne) {
  const char* stacks[] = {
      R"({"type":"layered","top":{"type":"dielectric","eta":1.5},"bottom":{"type":"roughdielectric","eta":1.3,"alpha":0.2,"multiscatter":true},"thickness":0})",
      R"({"type":"layered","top":{"type":"roughdielectric","eta":1.5,"alpha":0.3,"multiscatter":true},"bottom":{"type":"dielectric","eta":0.8},"thickness":0.5,"albedo":1,"g":0.3})",
      R"({"type":"layered","top":{"type":"thindielectric","eta":1.5},"bottom":{"type":"thindielectric","eta":1.33},"thickness":0.3,"albedo":1,"g":-0.3})",
  };
  const int n = int(test::scaled(20000));
  for (const char* desc : stacks) {
    const BxDF m = parse_material(desc);
    for (double th : {0.0, 40.0, 75.0, 100.0, 150.0, 180.0}) {
      const LayeredMean a = layered_albedo(m, layered_test_dir(th, 20), n, 5);
      const double slack = std::string(desc).find("rough") != std::string::npos ? 1.2e-2 : 1e-4;
      EXPECT_NEAR(a.mean, 1.0, 4.5 * a.se + slack) << desc << " at " << th << " deg";
    }
  }
}

// A glass slab (n 1.5 in air: the top's eta 1.5, the bottom's 1/1.5) with an absorbing
// interior of optical depth τ: the delta lobes are the incoherent sums
//   T = (1 − F)² A / (1 − F² A²),  R = F + (1 − F)² F A² / (1 − F² A²),  A = e^{−τ/μ'},
// μ' the cosine inside, F the Fresnel reflectance above (the same at Snell's pair of
// angles); the same from below.
TEST(Layered, GlassSlabIsTheIncoherentSum) {
  const double eta = 1.5, tau = 0.3;
  const BxDF slab = parse_material(
      R"({"type":"layered","top":{"type":"dielectric","eta":1.5},"bottom":{"type":"dielectric","eta":0.6666666667},"thickness":0.3})");
  for (double th : {0.0, 35.0, 70.0, 89.0}) {
    const double c = std::cos(th * kPiD / 180), F = layered_test_fresnel(c, eta);
    const double mu_in = std::sqrt(1 - (1 - c * c) / (eta * eta)), A = std::exp(-tau / mu_in);
    const double T = (1 - F) * (1 - F) * A / (1 - F * F * A * A);
    const double R = F + (1 - F) * (1 - F) * F * A * A / (1 - F * F * A * A);
    for (const double side : {1.0, -1.0}) {
      Vec3 wo = layered_test_dir(th, 25);
      wo.z *= Float(side);
      Pcg32 rng(77);
      const int n = int(test::scaled(20000));
      double sr = 0, st = 0;
      for (int i = 0; i < n; ++i) {
        const auto smp = slab.sample(wo, rng.next_float(), rng.next_float(), rng.next_float());
        if (!smp) continue;
        ASSERT_TRUE(smp->delta);
        (smp->wi.z * wo.z > 0 ? sr : st) += smp->weight[0];
      }
      // The chain is one random path per sample: 4.5 standard errors of a 0/1-like estimate.
      const double se = 1 / std::sqrt(double(n));
      EXPECT_NEAR(sr / n, R, 4.5 * se * std::sqrt(R) + 1e-5) << th << " side " << side;
      EXPECT_NEAR(st / n, T, 4.5 * se * std::sqrt(T) + 1e-5) << th << " side " << side;
    }
  }
}

// The mixture's components for light through the stack (the bottom's sampling through
// the top, a rough top's transmission through a delta bottom by Snell's law, from above
// and below, the far side's cosine lobe) sample the density pdf() returns: the validator's
// chi² and pdf integral. (Their `weights` exceed 100 × the albedo for rough interfaces
// near total internal reflection: docs/testing.md.)
TEST(Layered, TransmittingSamplingMatchesItsDensity) {
  const char* stacks[] = {
      R"({"type":"layered","top":{"type":"roughdielectric","eta":1.4,"alpha":0.3},"bottom":{"type":"dielectric","eta":0.8},"thickness":0})",
      R"({"type":"layered","top":{"type":"roughdielectric","eta":1.5,"alpha":0.3},"bottom":{"type":"roughdielectric","eta":1.3,"alpha":0.2},"thickness":0.5,"albedo":0.8,"g":0.3})",
  };
  ValidationOptions opt;
  opt.scale = double(test::scaled(250000, 25000)) / 1e6;  // a quarter of gonio check's counts
  for (const char* desc : stacks)
    for (const PropertyResult& p : check_sampling(parse_material(desc), opt))
      EXPECT_TRUE(p.pass) << desc << ": " << p.name << " " << p.detail;
}

TEST(Layered, RefusesWhatItCannotStack) {
  const auto message = [](const char* desc) {
    try {
      parse_material(desc);
    } catch (const InputError& e) {
      return std::string(e.what());
    }
    return std::string("(accepted)");
  };
  EXPECT_NE(message(R"({"type":"layered","top":{"type":"conductor","eta":1,"k":1},"bottom":{"type":"diffuse"}})")
                .find("top must be a dielectric, roughdielectric or thindielectric material, got type \"conductor\""),
            std::string::npos);
  EXPECT_NE(message(R"({"type":"layered","top":{"type":"dielectric"},"bottom":{"type":"diffuse"},"max_depth":2.5})")
                .find("max_depth must be a whole number"),
            std::string::npos);
  EXPECT_NE(message(R"({"type":"layered","top":{"type":"dielectric"},"bottom":{"type":"diffuse"},"g":0.95})").find("g must be"),
            std::string::npos);
  EXPECT_NE(message(R"({"type":"layered","top":{"type":"dielectric"}})").find("missing parameter 'bottom'"), std::string::npos);
  EXPECT_NE(message(R"({"type":"layered","top":{"type":"dielectric"},"bottom":{"type":"diffuse","reflectance":2}})")
                .find("layered.bottom: diffuse: reflectance"),
            std::string::npos);
}

}  // namespace
}  // namespace gonio
