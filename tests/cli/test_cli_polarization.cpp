// `gonio fresnel --mueller`, `gonio eval --polarized`, `gonio sample --polarized` (SPEC §1,
// §3; issue 15). Expectations from Fresnel's equations written here (Born & Wolf §1.5.2,
// p along k × s), the Stokes definition of docs/polarization.md, and the printed
// unpolarized fields (M00 must equal them exactly).

#include <gtest/gtest.h>

#include <cmath>
#include <complex>
#include <string>
#include <vector>

#include "run_gonio.h"

namespace {

using namespace gonio_cli_test;
using cxd = std::complex<double>;

struct PolAmp {
  cxd rs, rp;
};
PolAmp pol_fresnel(double cos_i, cxd n) {
  const cxd cos_t = std::sqrt(1.0 - (1 - cos_i * cos_i) / (n * n));
  return {(cos_i - n * cos_t) / (cos_i + n * cos_t), (n * cos_i - cos_t) / (n * cos_i + cos_t)};
}

// A printed 4×4 matrix: four rows of four numbers.
bool is_4x4(const json& m) {
  if (!m.is_array() || m.size() != 4) return false;
  for (const auto& row : m)
    if (!row.is_array() || row.size() != 4 || !row[0].is_number()) return false;
  return true;
}

TEST(CliPolarization, FresnelMuellerReflectionAndTransmission) {
  const double theta = 35;
  const json j = run_one({"fresnel", "--eta", "1.5", "--theta", "35", "--mueller"});
  ASSERT_TRUE(is_4x4(j["mueller_r"])) << j.dump();
  ASSERT_TRUE(is_4x4(j["mueller_t"])) << j.dump();
  const auto& r = j["mueller_r"];
  const auto& t = j["mueller_t"];
  EXPECT_EQ(r[0][0].get<double>(), j["R"].get<double>());
  EXPECT_EQ(t[0][0].get<double>(), j["T"].get<double>());
  const PolAmp a = pol_fresnel(std::cos(theta * M_PI / 180), 1.5);
  EXPECT_NEAR(r[0][1].get<double>(), (std::norm(a.rs) - std::norm(a.rp)) / 2, 1e-12);
  EXPECT_NEAR(r[2][2].get<double>(), (a.rs * std::conj(a.rp)).real(), 1e-12);
  EXPECT_NEAR(t[0][1].get<double>(), (std::norm(a.rp) - std::norm(a.rs)) / 2, 1e-12);
  // The unpolarized fields are unchanged by --mueller.
  const json plain = run_one({"fresnel", "--eta", "1.5", "--theta", "35"});
  EXPECT_EQ(plain["R"], j["R"]);
  EXPECT_FALSE(plain.contains("mueller_r"));
}

TEST(CliPolarization, FresnelMuellerAtBrewsterAndUnderTotalInternalReflection) {
  // Brewster (tan θ = 1.5): Rp = 0, so M00 = M01 (pure s).
  const json b = run_one({"fresnel", "--eta", "1.5", "--theta", std::to_string(std::atan(1.5) * 180 / M_PI), "--mueller"});
  EXPECT_NEAR(b["mueller_r"][0][1].get<double>(), b["mueller_r"][0][0].get<double>(), 1e-9);
  // From glass (eta = 1/1.5) at 60°: total, with retardance tan(δ/2) = cos θ √(sin²θ − n²)/sin²θ.
  const json t = run_one({"fresnel", "--eta", "0.6666666666666666", "--theta", "60", "--mueller"});
  const double th = 60 * M_PI / 180, n = 1 / 1.5, s2 = std::sin(th) * std::sin(th);
  const double delta = std::atan2(t["mueller_r"][3][2].get<double>(), t["mueller_r"][2][2].get<double>());
  EXPECT_NEAR(std::tan(delta / 2), std::cos(th) * std::sqrt(s2 - n * n) / s2, 1e-9);
  for (const auto& row : t["mueller_t"])
    for (const auto& v : row) EXPECT_EQ(v.get<double>(), 0.0);
}

TEST(CliPolarization, FresnelMuellerConductorAndNamedMaterials) {
  const json c = run_one({"fresnel", "--eta", "0.27", "--k", "2.78", "--theta", "70", "--mueller"});
  ASSERT_TRUE(is_4x4(c["mueller_r"]));
  EXPECT_FALSE(c.contains("mueller_t"));  // a conductor transmits nothing
  const PolAmp a = pol_fresnel(std::cos(70 * M_PI / 180), cxd(0.27, 2.78));
  const cxd z = a.rs * std::conj(a.rp);
  EXPECT_NEAR(c["mueller_r"][3][2].get<double>(), z.imag(), 1e-12);
  EXPECT_NEAR(c["mueller_r"][2][3].get<double>(), -z.imag(), 1e-12);
  // A named metal in RGB mode: one matrix per channel; each line of a range too.
  const auto lines = run_lines({"fresnel", "--material", "Au", "--theta-range", "0", "80", "3", "--mueller"}, "", 3);
  for (const auto& l : lines) {
    ASSERT_TRUE(l["mueller_r"].is_array() && l["mueller_r"].size() == 3) << l.dump();
    for (int ch = 0; ch < 3; ++ch) {
      ASSERT_TRUE(is_4x4(l["mueller_r"][ch]));
      EXPECT_EQ(l["mueller_r"][ch][0][0].get<double>(), l["R"][ch].get<double>());
    }
  }
  // A glass at one wavelength: numbers, one matrix, and mueller_t.
  const json g = run_one({"fresnel", "--material", "BK7", "--wavelength", "589.3", "--theta", "45", "--mueller"});
  EXPECT_TRUE(is_4x4(g["mueller_r"]));
  EXPECT_TRUE(is_4x4(g["mueller_t"]));
}

TEST(CliPolarization, EvalPolarizedHasM00EqualToF) {
  const std::string in = "0.6 0 0.8  -0.3 0.4 0.866\n0 0 1  0.2 -0.1 0.97\n0.5 0.5 0.7  0.1 0.2 -0.9\n";
  for (const std::string bsdf : {R"({"type":"roughconductor","alpha":0.3,"material":"Au"})",
                                 R"({"type":"roughdielectric","alpha":0.4,"eta":1.5})",
                                 R"({"type":"plastic","alpha":0.2,"reflectance":[0.2,0.4,0.6]})",
                                 R"({"type":"diffuse","reflectance":0.5})"}) {
    const auto lines = run_lines({"eval", "--bsdf", bsdf, "--polarized"}, in, 3);
    for (const auto& l : lines) {
      ASSERT_TRUE(l["mueller"].is_array() && l["mueller"].size() == 3) << l.dump();
      for (int ch = 0; ch < 3; ++ch) {
        ASSERT_TRUE(is_4x4(l["mueller"][ch])) << l.dump();
        EXPECT_EQ(l["mueller"][ch][0][0].get<double>(), l["f"][ch].get<double>()) << bsdf;
      }
    }
    // The diffuse model depolarizes: only M00.
    if (bsdf.find("diffuse") != std::string::npos) {
      for (int i = 0; i < 4; ++i)
        for (int j = 0; j < 4; ++j) {
          if (i || j) {
            EXPECT_EQ(lines[0]["mueller"][0][i][j].get<double>(), 0.0);
          }
        }
    }
  }
  // Spectral: one matrix.
  const auto s = run_lines({"eval", "--bsdf", R"({"type":"roughconductor","alpha":0.3,"material":"Cu"})", "--polarized",
                            "--wavelength", "600"},
                           "0.6 0 0.8  -0.3 0.4 0.866\n", 1);
  ASSERT_EQ(s[0]["mueller"].size(), 1u);
  EXPECT_EQ(s[0]["mueller"][0][0][0].get<double>(), s[0]["f"][0].get<double>());
  EXPECT_NE(s[0]["mueller"][0][0][1].get<double>(), 0.0);
  // Without --polarized no "mueller".
  EXPECT_FALSE(run_lines({"eval", "--bsdf", R"({"type":"diffuse"})"}, "0 0 1 0 0 1\n", 1)[0].contains("mueller"));
}

TEST(CliPolarization, SamplePolarizedHasM00EqualToWeight) {
  const auto lines = run_lines({"sample", "--bsdf", R"({"type":"dielectric","eta":1.5})", "--polarized"},
                               "0.6 0 0.8 0.01 0.5 0.5\n0.6 0 0.8 0.99 0.5 0.5\n", 2);
  for (const auto& l : lines) {
    ASSERT_TRUE(l["mueller"].is_array() && l["mueller"].size() == 3) << l.dump();
    EXPECT_EQ(l["mueller"][0][0][0].get<double>(), l["weight"][0].get<double>());
  }
  EXPECT_EQ(lines[0]["lobe"], "reflection");
  EXPECT_EQ(lines[1]["lobe"], "transmission");
  // Reflection at 36.9°, weight 1: M01 = (Rs − Rp)/(Rs + Rp) of the test's Fresnel.
  const PolAmp a = pol_fresnel(0.8, 1.5);
  const double rs = std::norm(a.rs), rp = std::norm(a.rp);
  EXPECT_NEAR(lines[0]["mueller"][0][0][1].get<double>(), (rs - rp) / (rs + rp), 1e-5);
}

TEST(CliPolarization, PolarizedOptionsKeepTheErrorContract) {
  expect_bad_input(run_gonio({"eval", "--bsdf", R"({"type":"nope"})", "--polarized"}, "0 0 1 0 0 1\n"), {"nope"});
  expect_bad_input(run_gonio({"eval", "--bsdf", R"({"type":"diffuse"})", "--polarized"}, "0 0 0 0 0 1\n"), {"wo"});
  expect_bad_input(run_gonio({"sample", "--bsdf", R"({"type":"diffuse"})", "--polarized"}, "0 0 1 2 0 0\n"), {"u0"});
  expect_bad_input(run_gonio({"fresnel", "--eta", "-1", "--theta", "10", "--mueller"}), {"--eta"});
  // albedo accepts --polarized (SPEC §3) with the same output.
  const json a0 = run_one({"albedo", "--bsdf", R"({"type":"dielectric"})", "--theta", "30"});
  EXPECT_EQ(run_one({"albedo", "--bsdf", R"({"type":"dielectric"})", "--theta", "30", "--polarized"}), a0);
  expect_bad_input(run_gonio({"fresnel", "--eta", "1.5", "--theta", "10", "--mueller=maybe"}), {"mueller"});
}

}  // namespace
