// Calibration of the gantry on flat samples, against closed forms computed here:
// Lambert's ρ/π, Fresnel's equations (Born & Wolf §1.5 and §13.2, complex index for
// the conductor) and Snell's law.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <complex>
#include <vector>

#include "../test_common.h"
#include "../unit/test_scale.h"
#include "gonio/error.h"
#include "gonio/material.h"
#include "gonio/measure/gantry.h"
#include "gonio/measure/instrument.h"
#include "surfaces_for_tests.h"

namespace gonio::measure {
namespace {


// Unpolarised Fresnel reflectance from a medium of index 1 onto index n (complex for a
// conductor), Born & Wolf eqs. 1.5 (20) and 13.2.
double fresnel(double theta, std::complex<double> n) {
  const double c = std::cos(theta), s2 = std::sin(theta) * std::sin(theta);
  const std::complex<double> root = std::sqrt(n * n - s2);
  const double rs = std::norm((c - root) / (c + root));
  const double rp = std::norm((n * n * c - root) / (n * n * c + root));
  return (rs + rp) / 2;
}

// A full block puts one ray in each cell of the 128 × 64 strata, in Morton order: ray k's
// cell is k's even bits (column) and odd bits (row), gathered here bit by bit.
TEST(EntryPoint, FullBlockVisitsEveryStratumOnceInMortonOrder) {
  Pcg32 rng(5, 9);
  std::vector<int> seen(kBlockRays, 0);
  for (std::uint64_t k = 0; k < kBlockRays; ++k) {
    double u, v;
    entry_point(k, true, rng, u, v);
    ASSERT_TRUE(u >= 0 && u < 1 && v >= 0 && v < 1) << k;
    const int col = int(std::floor(u * 128)), row = int(std::floor(v * 64));
    int want_col = 0, want_row = 0;
    for (int b = 0; b < 13; ++b) (b % 2 == 0 ? want_col : want_row) |= int((k >> b) & 1) << (b / 2);
    EXPECT_EQ(col, want_col) << k;
    EXPECT_EQ(row, want_row) << k;
    ++seen[std::size_t(row * 128 + col)];
  }
  EXPECT_EQ(std::count(seen.begin(), seen.end(), 1), std::ptrdiff_t(kBlockRays));
}

TEST(Gantry, ConeProjectedSolidAngle) {
  // Above the horizon: π sin²β cos θc; a cone on the horizon keeps the half above it,
  // ∫ cos over a small cone cut through its axis ≈ ∫∫ y dy dx over a half disc = 2β³/3.
  EXPECT_NEAR(cone_projected_solid_angle(30 * kDeg, 5 * kDeg),
              kPiD * std::pow(std::sin(5 * kDeg), 2) * std::cos(30 * kDeg), 1e-12);
  EXPECT_NEAR(cone_projected_solid_angle(150 * kDeg, 5 * kDeg),
              kPiD * std::pow(std::sin(5 * kDeg), 2) * std::cos(30 * kDeg), 1e-12);
  const double b = 2 * kDeg;
  EXPECT_NEAR(cone_projected_solid_angle(90 * kDeg - 1e-9, b) / (2 * b * b * b / 3), 1, 2e-3);
  // Continuous where the closed form takes over.
  EXPECT_NEAR(cone_projected_solid_angle(85 * kDeg - 1e-9, 5 * kDeg),
              cone_projected_solid_angle(85 * kDeg + 1e-9, 5 * kDeg), 1e-6);
}

GantrySpec lambert_spec() {
  GantrySpec g;
  g.theta_i = {0, 30, 60, 85};
  g.phi_i = {0};
  g.theta_o = {5, 15, 25, 35, 45, 55, 65, 75};
  g.phi_o = {0, 90, 180};
  g.aperture = 5;
  return g;
}

// A flat Lambertian: the albedo is ρ at every θi, and every detector reads ρ/π within its
// standard error (χ² over the detectors).
TEST(Gantry, FlatLambertianIsCalibrated) {
  const Microsurface s(testsurf::flat_field(), parse_material(R"({"type":"diffuse","reflectance":[0.2,0.5,0.8]})"));
  const GantrySpec g = lambert_spec();
  RunOptions o;
  o.samples = gonio::test::scaled(400000, 40000) * g.theta_i.size();
  o.seed = 5;
  const GantryReading r = run_gantry(s, g, o);
  const double rho[3] = {0.2, 0.5, 0.8};
  for (const IncidenceReading& inc : r.incidences) {
    double chi2 = 0;
    int dof = 0;
    for (int c = 0; c < 3; ++c) {
      EXPECT_NEAR(inc.albedo[c], rho[c], 0.01 * rho[c]) << "theta_i " << inc.theta_i;
      EXPECT_NEAR(inc.transmittance[c], 0, 1e-12);
    }
    for (const DetectorReading& d : inc.detectors) {
      ASSERT_GT(d.stderr_f[1], 0);
      const double z = (d.f[1] - rho[1] / kPiD) / d.stderr_f[1];
      chi2 += z * z;
      ++dof;
      EXPECT_NEAR(d.f[0] / d.f[1], 0.2 / 0.5, 1e-5);  // one ray, one weight per channel
    }
    // χ² with 24 degrees of freedom: its 99.9% quantile is 51.2.
    EXPECT_LT(chi2, 51.2) << "theta_i " << inc.theta_i;
    EXPECT_GT(chi2, 5.0) << "theta_i " << inc.theta_i << ": standard errors too large";
  }
}

// A flat conductor puts all the power into the specular detector, with reflectance F(θi).
TEST(Gantry, FlatConductorReflectsFresnelIntoTheSpecularDetector) {
  const Microsurface s(testsurf::flat_field(),
                       parse_material(R"({"type":"conductor","eta":[0.2,0.9,1.2],"k":[3.6,2.6,2.4]})"));
  GantrySpec g;
  g.theta_i = {0, 20, 45, 70, 85};
  g.phi_i = {30};
  for (const double t : g.theta_i) g.theta_o.push_back(t);
  g.phi_o = {210, 30};
  g.aperture = 1;
  RunOptions o;
  o.samples = 2000 * g.theta_i.size();
  const GantryReading r = run_gantry(s, g, o);
  const std::complex<double> n[3] = {{0.2, 3.6}, {0.9, 2.6}, {1.2, 2.4}};
  for (std::size_t a = 0; a < g.theta_i.size(); ++a) {
    const IncidenceReading& inc = r.incidences[a];
    for (int c = 0; c < 3; ++c) {
      const double F = fresnel(g.theta_i[a] * kDeg, n[c]);
      EXPECT_NEAR(inc.albedo[c], F, 1e-5 * F) << "theta_i " << g.theta_i[a];
      for (const DetectorReading& d : inc.detectors) {
        const bool specular = d.theta_o == g.theta_i[a] && (d.phi_o == 210 || g.theta_i[a] == 0);
        EXPECT_NEAR(d.f[c] * d.solid_angle, specular ? F : 0.0, 1e-5) << d.theta_o << " " << d.phi_o;
      }
    }
  }
}

// A flat glass transmits 1 − F (power: importance transport) along Snell's direction.
TEST(Gantry, FlatGlassTransmitsOneMinusFresnelAlongSnell) {
  const Microsurface s(testsurf::flat_field(), parse_material(R"({"type":"dielectric","eta":1.5})"));
  GantrySpec g;
  g.theta_i = {0, 30, 60, 80};
  g.phi_i = {0};
  for (const double t : g.theta_i) g.theta_o.push_back(180 - std::asin(std::sin(t * kDeg) / 1.5) / kDeg);
  g.phi_o = {180};
  g.aperture = 0.5;
  RunOptions o;
  o.samples = gonio::test::scaled(200000, 40000) * g.theta_i.size();
  const GantryReading r = run_gantry(s, g, o);
  for (std::size_t a = 0; a < g.theta_i.size(); ++a) {
    const IncidenceReading& inc = r.incidences[a];
    const double F = fresnel(g.theta_i[a] * kDeg, 1.5);
    // Each ray is reflected or refracted whole: binomial noise.
    const double se = std::sqrt(F * (1 - F) / double(r.rays_per_incidence));
    EXPECT_NEAR(inc.transmittance[1], 1 - F, 4 * se + 1e-6) << "theta_i " << g.theta_i[a];
    EXPECT_NEAR(inc.albedo[1], F, 4 * se + 1e-6) << "theta_i " << g.theta_i[a];
    EXPECT_NEAR(inc.albedo[1] + inc.transmittance[1], 1, 1e-5);
    const DetectorReading& d = inc.detectors[a];  // the Snell direction of this incidence
    EXPECT_NEAR(d.f[1] * d.solid_angle, inc.transmittance[1], 1e-5) << "theta_i " << g.theta_i[a];
  }
}

// Reciprocity of the raw measurement: light at ωi and detector at ωo read the same f as
// light at ωo and detector at ωi, on a rough diffuse microsurface.
TEST(Gantry, ReciprocalUnderSwappedLightAndDetector) {
  const Microsurface s(testsurf::eggcrate_field(32, 4), parse_material(R"({"type":"diffuse","reflectance":0.8})"));
  struct Dir {
    double theta, phi;
  };
  const Dir dirs[] = {{20, 0}, {55, 180}, {40, 90}};
  RunOptions o;
  o.samples = gonio::test::scaled(100000, 30000);
  o.seed = 9;
  int pairs = 0;
  // One run per incidence with detectors at the other directions (a detector list is a
  // product of θo × φo, so one detector per run keeps the pairing explicit).
  auto reading = [&](const Dir& light, const Dir& det) {
    GantrySpec q;
    q.theta_i = {light.theta};
    q.phi_i = {light.phi};
    q.theta_o = {det.theta};
    q.phi_o = {det.phi};
    q.aperture = 6;
    return run_gantry(s, q, o).incidences[0].detectors[0];
  };
  for (int a = 0; a < 3; ++a)
    for (int b = a + 1; b < 3; ++b) {
      const DetectorReading x = reading(dirs[a], dirs[b]), y = reading(dirs[b], dirs[a]);
      const double se = std::hypot(x.stderr_f[0], y.stderr_f[0]);
      ASSERT_GT(se, 0);
      const double z = (x.f[0] - y.f[0]) / se;
      EXPECT_LT(std::abs(z), 4) << a << " " << b << ": " << x.f[0] << " vs " << y.f[0];
      ++pairs;
    }
  EXPECT_EQ(pairs, 3);
}

TEST(Gantry, SameBitsWhateverTheThreadCount) {
  const Microsurface s(testsurf::eggcrate_field(16, 2), parse_material(R"({"type":"diffuse","reflectance":0.7})"));
  GantrySpec g = lambert_spec();
  RunOptions o;
  o.samples = 100000;
  o.threads = 1;
  const GantryReading a = run_gantry(s, g, o);
  o.threads = 2;
  const GantryReading b = run_gantry(s, g, o);
  for (std::size_t i = 0; i < a.incidences.size(); ++i) {
    EXPECT_EQ(a.incidences[i].albedo, b.incidences[i].albedo);
    for (std::size_t d = 0; d < a.incidences[i].detectors.size(); ++d)
      EXPECT_EQ(a.incidences[i].detectors[d].f, b.incidences[i].detectors[d].f);
  }
}

TEST(Gantry, BadSpecIsOneLineInputError) {
  for (const char* bad : {R"({"theta_i":[0]})", R"({"theta_o":90})", R"({"theta_o":[10],"theta_i":95})",
                          R"({"theta_o":{"from":0,"to":80}})", R"({"theta_o":[10],"aperture":0})",
                          R"({"theta_o":[10],"aperture":1e-300})",  // a cone of no solid angle
                          R"({"theta_o":[10],"colour":1})", R"([1,2])", R"({"theta_o":"x"})"}) {
    try {
      parse_gantry(bad);
      ADD_FAILURE() << bad;
    } catch (const InputError& e) {
      EXPECT_EQ(std::string(e.what()).find('\n'), std::string::npos);
      EXPECT_NE(std::string(e.what()).find("--gantry"), std::string::npos) << e.what();
    }
  }
  const GantrySpec g = parse_gantry(R"({"theta_o":{"from":0,"to":80,"count":5},"phi_o":[0,180]})");
  ASSERT_EQ(g.theta_o.size(), 5u);
  EXPECT_EQ(g.theta_o[4], 80);
  EXPECT_EQ(g.aperture, 2);
}

TEST(Gantry, ReadingsAreBoundedAtAMillion) {
  // incidences x detectors: 1000 x 1000 is accepted, 1000 x 1001 refused before any ray
  // (10^4 x 10^4 once traced for 96 s and then ran out of memory).
  const GantrySpec at = parse_gantry(R"({"theta_i":{"from":0,"to":80,"count":1000},)"
                                     R"("theta_o":{"from":0,"to":80,"count":1000}})");
  EXPECT_EQ(at.theta_i.size() * at.theta_o.size(), kMaxGantryReadings);
  try {
    parse_gantry(R"({"theta_i":{"from":0,"to":80,"count":1000},"theta_o":{"from":0,"to":80,"count":1001}})");
    ADD_FAILURE() << "1001000 readings were accepted";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("--gantry: 1000 incidences x 1001 detectors = 1001000 readings"),
              std::string::npos)
        << e.what();
    EXPECT_NE(std::string(e.what()).find("1000000"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace gonio::measure
