// `--wavelength NM` on the command line (SPEC §1 "Spectral mode", §3): eval, sample and
// albedo evaluate the material at one wavelength and print every colour as a one-element
// array; fresnel takes a named metal's or glass's index at that wavelength and prints the
// index used. Expectations come from closed forms written here (Fresnel's equations,
// the GGX distribution and Smith masking), Schott's Sellmeier formula and the tests' own
// reading of data/metals/*.csv (tests/data_csv.h) — never from gonio's code.

#include <gtest/gtest.h>

#include <cmath>
#include <complex>
#include <string>
#include <vector>

#include "../data_csv.h"
#include "run_gonio.h"

namespace {

using namespace gonio_cli_test;
using gonio_test_data::lerp_rows;
using gonio_test_data::read_data;

// Unpolarised Fresnel reflectance at incidence cos_i onto relative index n (complex for a
// conductor, n = η + i k): r_s = (cos i − n cos t)/(cos i + n cos t),
// r_p = (n cos i − cos t)/(n cos i + cos t), n sin t = sin i (Born & Wolf, Principles of
// Optics, 7th ed., §1.5.2 eqs. 20–21; §14.2 for the complex index). R = (|r_s|² + |r_p|²)/2.
struct Fresnel {
  double rs, rp;
  double r() const { return (rs + rp) / 2; }
};
Fresnel fresnel(double cos_i, std::complex<double> n) {
  const double sin2 = 1 - cos_i * cos_i;
  const std::complex<double> cos_t = std::sqrt(1.0 - sin2 / (n * n));
  const std::complex<double> rs = (cos_i - n * cos_t) / (cos_i + n * cos_t);
  const std::complex<double> rp = (n * cos_i - cos_t) / (n * cos_i + cos_t);
  return {std::norm(rs), std::norm(rp)};
}

// Schott's Sellmeier formula for N-BK7: n² − 1 = Σ B_i λ² / (λ² − C_i), λ in µm
// (Schott optical glass data sheet N-BK7: B1 = 1.03961212, B2 = 0.231792344,
// B3 = 1.01046945, C1 = 0.00600069867, C2 = 0.0200179144, C3 = 103.560653 µm²).
double bk7_sellmeier(double nm) {
  const double l2 = (nm / 1000) * (nm / 1000);
  const double b[3] = {1.03961212, 0.231792344, 1.01046945};
  const double c[3] = {0.00600069867, 0.0200179144, 103.560653};
  double s = 1;
  for (int i = 0; i < 3; ++i) s += b[i] * l2 / (l2 - c[i]);
  return std::sqrt(s);
}

// A colour printed in spectral mode: a one-element array holding a number.
double one(const json& v) {
  EXPECT_TRUE(v.is_array() && v.size() == 1 && v[0].is_number()) << "expected [v], got " << v.dump();
  return v.is_array() && v.size() == 1 && v[0].is_number() ? v[0].get<double>() : NAN;
}

TEST(CliWavelength, GreyDiffuseIsReflectanceOverPiAtEveryWavelength) {
  // f = ρ/π for Lambert (SPEC §2), whatever λ: a flat spectrum is exact; an RGB grey is
  // upsampled (Jakob & Hanika 2019), whose fit reproduces a grey to its table's accuracy.
  const std::string flat = R"({"type":"diffuse","reflectance":{"spectrum":[[360,0.37],[830,0.37]]}})";
  const std::string rgb = R"({"type":"diffuse","reflectance":0.37})";
  for (const char* nm : {"360", "455.5", "589.3", "700", "830"}) {
    const auto lines = run_lines({"eval", "--bsdf", flat, "--wavelength", nm}, "0 0 1 0.3 0.2 0.9\n0.6 0 0.8 0 0 1\n", 2);
    for (const auto& j : lines) {
      EXPECT_NEAR(one(j["f"]), 0.37 / kPi, 1e-7) << nm << ": " << j.dump();
      EXPECT_TRUE(j["pdf"].is_number()) << j.dump();
    }
    const json g = run_one({"eval", "--bsdf", rgb, "--wavelength", nm}, "0 0 1 0.3 0.2 0.9\n");
    EXPECT_NEAR(one(g["f"]), 0.37 / kPi, 0.01 * 0.37 / kPi) << nm << ": " << g.dump();
  }
}

TEST(CliWavelength, Bk7FresnelAt589nmFollowsSellmeierAndFresnel) {
  const double nm = 589.3;
  const double n = bk7_sellmeier(nm);  // 1.5168
  for (double theta : {0.0, 30.0, 56.0, 80.0}) {
    const json j = run_one({"fresnel", "--material", "BK7", "--wavelength", fmt(nm), "--theta", fmt(theta)});
    // data/glasses/BK7.csv is tabulated every 22 nm; its linear interpolation is within
    // 2e-5 of the formula there (|n''| h² / 8).
    EXPECT_NEAR(num(j, "eta"), n, 2e-5) << j.dump();
    EXPECT_EQ(num(j, "k"), 0) << j.dump();
    const Fresnel f = fresnel(std::cos(deg(theta)), n);
    // dR/dn is at most ~0.3 over these angles: 2e-5 in n is < 1e-5 in R.
    EXPECT_NEAR(num(j, "Rs"), f.rs, 1e-5) << theta << " " << j.dump();
    EXPECT_NEAR(num(j, "Rp"), f.rp, 1e-5) << theta << " " << j.dump();
    EXPECT_NEAR(num(j, "R"), f.r(), 1e-5) << theta << " " << j.dump();
    EXPECT_NEAR(num(j, "T"), 1 - f.r(), 1e-5) << theta << " " << j.dump();
    // Snell: cos θt = sqrt(1 − sin²θ / n²).
    const double s = std::sin(deg(theta));
    EXPECT_NEAR(num(j, "cos_t"), std::sqrt(1 - s * s / (n * n)), 1e-5) << j.dump();
  }
}

TEST(CliWavelength, GoldIndexAt550nmIsTheCsvInterpolated) {
  const auto au = read_data("metals/Au.csv");
  ASSERT_GT(au.size(), 10u);
  const double n = lerp_rows(au, 550, 1), k = lerp_rows(au, 550, 2);
  const auto lines = run_lines({"fresnel", "--material", "Au", "--wavelength", "550", "--theta-range", "0", "80", "3"}, "", 3);
  for (size_t i = 0; i < lines.size(); ++i) {
    const json& j = lines[i];
    // The tool holds the index in float: 1e-6 relative.
    EXPECT_NEAR(num(j, "eta"), n, 1e-6 * n) << j.dump();
    EXPECT_NEAR(num(j, "k"), k, 1e-6 * k) << j.dump();
    const double theta = 40.0 * double(i);
    const Fresnel f = fresnel(std::cos(deg(theta)), {n, k});
    EXPECT_NEAR(num(j, "R"), f.r(), 1e-5) << theta << " " << j.dump();
    EXPECT_NEAR(num(j, "Rs"), f.rs, 1e-5) << theta << " " << j.dump();
    EXPECT_NEAR(num(j, "Rp"), f.rp, 1e-5) << theta << " " << j.dump();
    EXPECT_TRUE(j["cos_t"].is_null()) << j.dump();  // a conductor (SPEC §3)
  }
}

TEST(CliWavelength, GoldConductorAt600nmIsFresnelWeighted) {
  const auto au = read_data("metals/Au.csv");
  const std::complex<double> n{lerp_rows(au, 600, 1), lerp_rows(au, 600, 2)};

  // Smooth conductor: its one delta sample's weight is F(cos θo) (SPEC §2: perfect
  // specular reflection with conductor Fresnel).
  for (double theta : {0.0, 45.0, 75.0}) {
    const double t = deg(theta);
    const json j = run_one({"sample", "--bsdf", R"({"type":"conductor","material":"Au"})", "--wavelength", "600"},
                           fmt(std::sin(t)) + " 0 " + fmt(std::cos(t)) + " 0.5 0.5 0.5\n");
    EXPECT_NEAR(one(j["weight"]), fresnel(std::cos(t), n).r(), 1e-5) << theta << " " << j.dump();
    EXPECT_EQ(j["delta"], true) << j.dump();
  }

  // Rough conductor (GGX, α = 0.3), eval: f = D(h) G2 F(wo·h) / (4 cos θo cos θi) with
  // D = α² / (π cos⁴θh (α² + tan²θh)²) (Walter et al. 2007, eq. 33), Smith
  // Λ(w) = (−1 + sqrt(1 + α² tan²θ)) / 2 (Heitz 2014, eq. 86) and the height-correlated
  // G2 = 1 / (1 + Λ(wo) + Λ(wi)) (Heitz 2014, eq. 99).
  const double a = 0.3;
  auto lambda = [a](double cos_t) {
    const double tan2 = (1 - cos_t * cos_t) / (cos_t * cos_t);
    return (-1 + std::sqrt(1 + a * a * tan2)) / 2;
  };
  const double wo[3] = {0.5, 0.1, std::sqrt(1 - 0.26)}, wi[3] = {-0.3, 0.2, std::sqrt(1 - 0.13)};
  double h[3] = {wo[0] + wi[0], wo[1] + wi[1], wo[2] + wi[2]};
  const double hl = std::sqrt(h[0] * h[0] + h[1] * h[1] + h[2] * h[2]);
  for (double& c : h) c /= hl;
  const double cos_h = h[2], tan2_h = (1 - cos_h * cos_h) / (cos_h * cos_h);
  const double d = a * a / (kPi * std::pow(cos_h, 4) * std::pow(a * a + tan2_h, 2));
  const double g2 = 1 / (1 + lambda(wo[2]) + lambda(wi[2]));
  const double cos_oh = wo[0] * h[0] + wo[1] * h[1] + wo[2] * h[2];
  const double f = d * g2 * fresnel(cos_oh, n).r() / (4 * wo[2] * wi[2]);
  std::string line;
  for (double c : wo) line += fmt(c) + " ";
  for (double c : wi) line += fmt(c) + " ";
  const json j = run_one({"eval", "--bsdf", R"({"type":"roughconductor","alpha":0.3,"material":"Au"})",
                          "--wavelength", "600"},
                         line + "\n");
  EXPECT_NEAR(one(j["f"]), f, 1e-4 * f) << j.dump();
}

TEST(CliWavelength, EveryColourIsAOneElementArray) {
  const std::string rough = R"({"type":"roughdielectric","alpha":0.2,"eta":"BK7"})";
  const json e = run_one({"eval", "--bsdf", rough, "--wavelength", "500"}, "0 0 1 0.1 0 -1\n");
  one(e["f"]);
  EXPECT_TRUE(e["pdf"].is_number()) << e.dump();

  const auto s = run_lines({"sample", "--bsdf", rough, "--wavelength", "500", "--count", "3"}, "0.2 0 1\n", 3);
  for (const auto& j : s) {
    if (j["wi"].is_null()) continue;
    one(j["weight"]);
    EXPECT_EQ(j["wi"].size(), 3u) << j.dump();  // a direction, not a colour
  }

  // Albedo: exact (diffuse: ρ), Monte Carlo (rough dielectric) and hemispherical.
  const json d = run_one({"albedo", "--bsdf", R"({"type":"diffuse","reflectance":{"spectrum":[[360,0.2],[830,0.6]]}})",
                          "--wavelength", "595", "--theta", "30"});
  // The spectrum at 595 nm: 0.2 + 0.4 (595 − 360) / 470 = 0.4.
  EXPECT_NEAR(one(d["reflectance"]), 0.4, 1e-6) << d.dump();
  EXPECT_NEAR(one(d["albedo"]), 0.4, 1e-6) << d.dump();
  EXPECT_EQ(one(d["transmittance"]), 0) << d.dump();
  for (const char* key : {"stderr", "stderr_reflectance", "stderr_transmittance"}) EXPECT_EQ(one(d[key]), 0) << d.dump();
  EXPECT_EQ(d["exact"], true) << d.dump();

  const json m = run_one({"albedo", "--bsdf", rough, "--wavelength", "500", "--theta", "20", "--samples", "20000"});
  for (const char* key : {"reflectance", "transmittance", "albedo", "stderr", "stderr_reflectance", "stderr_transmittance"})
    one(m[key]);
  // A rough dielectric loses little energy at α = 0.2 (single scattering): albedo near 1.
  EXPECT_GT(one(m["albedo"]), 0.9) << m.dump();
  EXPECT_LE(one(m["albedo"]), 1.0 + 4 * one(m["stderr"])) << m.dump();

  const json h = run_one({"albedo", "--bsdf", R"({"type":"diffuse","reflectance":0.5})", "--wavelength", "450",
                          "--hemispherical"});
  EXPECT_NEAR(one(h["albedo"]), 0.5, 0.005) << h.dump();
  EXPECT_TRUE(h["theta"].is_null()) << h.dump();
}

TEST(CliWavelength, MonteCarloAlbedoAtOneWavelength) {
  // Oren–Nayar with σ = 0 is Lambert (Oren & Nayar 1994, eq. 30: A = 1, B = 0), but has no
  // closed-form albedo in gonio, so albedo takes the Monte Carlo path: ρ_dh = ρ_hh = ρ(λ),
  // here 0.2 + 0.4 (595 − 360) / 470 = 0.4, nothing transmitted.
  const std::string on = R"({"type":"orennayar","sigma":0,"reflectance":{"spectrum":[[360,0.2],[830,0.6]]}})";
  for (const std::vector<std::string>& where : {std::vector<std::string>{"--theta", "50"}, {"--hemispherical"}}) {
    std::vector<std::string> args{"albedo", "--bsdf", on, "--wavelength", "595", "--samples", "4000"};
    args.insert(args.end(), where.begin(), where.end());
    const json j = run_one(args);
    EXPECT_EQ(j["exact"], false) << j.dump();
    const double se = one(j["stderr"]);
    EXPECT_NEAR(one(j["reflectance"]), 0.4, 1e-5 + 5 * se) << j.dump();
    EXPECT_NEAR(one(j["albedo"]), 0.4, 1e-5 + 5 * se) << j.dump();
    EXPECT_EQ(one(j["transmittance"]), 0) << j.dump();
  }
  // A property: a material whose spectra are flat is the same model at every wavelength
  // as in RGB mode, and the estimate uses the same samples, so the numbers agree.
  const std::string flat = R"({"type":"roughconductor","alpha":0.3,"eta":1.2,"k":3})";
  const json rgb = run_one({"albedo", "--bsdf", flat, "--theta", "40", "--samples", "3000", "--seed", "9"});
  const json spec = run_one({"albedo", "--bsdf", flat, "--theta", "40", "--samples", "3000", "--seed", "9", "--wavelength", "430"});
  for (const char* key : {"reflectance", "albedo", "stderr"})
    EXPECT_NEAR(one(spec[key]), color3(rgb[key])[1], 1e-6) << key << " " << spec.dump() << " " << rgb.dump();
}

TEST(CliWavelength, SmoothBk7ReflectsTheSellmeierFresnel) {
  // A smooth dielectric's albedo at one wavelength: reflectance F(θ, n(λ)) exactly, the
  // rest transmitted (importance mode: energy).
  const double n = bk7_sellmeier(486.1);
  const json j = run_one({"albedo", "--bsdf", R"({"type":"dielectric","eta":"BK7"})", "--wavelength", "486.1",
                          "--theta", "60"});
  const double r = fresnel(std::cos(deg(60)), n).r();
  EXPECT_NEAR(one(j["reflectance"]), r, 1e-5) << j.dump();
  EXPECT_NEAR(one(j["transmittance"]), 1 - r, 1e-5) << j.dump();
}

TEST(CliWavelength, BadWavelengthIsOneErrorLine) {
  const std::string bsdf = R"({"type":"diffuse"})";
  for (const char* bad : {"abc", "200", "1000", "nan", "inf", "359.9", "830.1", "", "550nm"}) {
    expect_bad_input(run_gonio({"eval", "--bsdf", bsdf, "--wavelength", bad}, "0 0 1 0 0 1\n"),
                     {"--wavelength", std::string("'") + bad + "'"});
    expect_bad_input(run_gonio({"sample", "--bsdf", bsdf, "--wavelength", bad}, "0 0 1 0.5 0.5 0.5\n"),
                     {"--wavelength", bad});
    expect_bad_input(run_gonio({"albedo", "--bsdf", bsdf, "--wavelength", bad, "--theta", "0"}), {"--wavelength", bad});
    expect_bad_input(run_gonio({"fresnel", "--material", "Au", "--wavelength", bad, "--theta", "0"}),
                     {"--wavelength", bad});
  }
  // The ends of the range are accepted.
  run_one({"eval", "--bsdf", bsdf, "--wavelength", "360"}, "0 0 1 0 0 1\n");
  run_one({"fresnel", "--material", "Ag", "--wavelength", "830", "--theta", "10"});
}

}  // namespace
