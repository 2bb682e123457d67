// gonio spectrum (SPEC §3): the printed spectrum checked against data/'s CIE tables by this
// file's own quadrature and the IEC 61966-2-1 matrix written out here, and the error
// contract for bad --rgb values.

#include <algorithm>
#include <array>
#include <cmath>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "../data_csv.h"
#include "run_gonio.h"

namespace gonio_cli_test {
namespace {

using gonio_test_data::lerp_rows;
using gonio_test_data::read_data;

// Linear sRGB of the printed spectrum (interpolated to 1 nm): under D65 for a reflectance,
// on its own for an emission; trapezoid rule.
std::array<double, 3> srgb_of(const json& out, bool emission) {
  static const auto cmf = read_data("cie/cie1931_2deg_cmf.csv");
  static const auto d65 = read_data("cie/cie_illuminant_d65.csv");
  std::vector<std::vector<double>> s;
  for (size_t i = 0; i < out["lambda"].size(); ++i) s.push_back({out["lambda"][i].get<double>(), out["values"][i].get<double>()});
  double xyz[3] = {}, norm = 0;
  for (const auto& c : cmf) {
    const double nm = c[0], h = (nm == 360 || nm == 830) ? 0.5 : 1.0;
    const double light = emission ? 1.0 : lerp_rows(d65, nm);
    const double v = lerp_rows(s, nm);
    for (int k = 0; k < 3; ++k) xyz[k] += h * v * light * c[size_t(k) + 1];
    norm += h * light * c[2];
  }
  for (double& v : xyz) v /= norm;
  return {3.2406 * xyz[0] - 1.5372 * xyz[1] - 0.4986 * xyz[2], -0.9689 * xyz[0] + 1.8758 * xyz[1] + 0.0415 * xyz[2],
          0.0557 * xyz[0] - 0.2040 * xyz[1] + 1.0570 * xyz[2]};
}

TEST(CliSpectrum, ReflectanceFormatBoundsAndRoundTrip) {
  for (const std::array<double, 3> in : {std::array<double, 3>{0.8, 0.3, 0.1}, {0.1, 0.5, 0.9}, {0.2, 0.9, 0.2}}) {
    const json out = run_one({"spectrum", "--rgb", fmt(in[0]), fmt(in[1]), fmt(in[2])});
    ASSERT_TRUE(out.contains("lambda") && out.contains("values") && out.contains("rgb")) << out.dump();
    ASSERT_EQ(out["lambda"].size(), 95u);
    ASSERT_EQ(out["values"].size(), 95u);
    for (size_t i = 0; i < 95; ++i) {
      EXPECT_EQ(out["lambda"][i].get<double>(), 360.0 + 5.0 * double(i));
      const double v = out["values"][i].get<double>();
      EXPECT_TRUE(v >= 0 && v <= 1) << v;
    }
    const auto rgb = color3(out["rgb"]);
    // The tool's own round trip (1 nm) and this file's from the printed 5 nm samples.
    const auto mine = srgb_of(out, false);
    for (size_t c = 0; c < 3; ++c) {
      EXPECT_NEAR(rgb[c], in[c], 2e-3) << out.dump();
      EXPECT_NEAR(mine[c], in[c], 4e-3) << c;
    }
  }
}

TEST(CliSpectrum, GreyIsFlat) {
  const json out = run_one({"spectrum", "--rgb", "0.5", "0.5", "0.5"});
  for (const auto& v : out["values"]) EXPECT_NEAR(v.get<double>(), 0.5, 1e-6);
}

TEST(CliSpectrum, WhiteEmissionIsD65AndStaysWhite) {
  const json out = run_one({"spectrum", "--rgb", "1", "1", "1", "--emission"});
  const auto rgb = color3(out["rgb"]);
  for (double v : rgb) EXPECT_NEAR(v, 1.0, 1e-3);
  const auto mine = srgb_of(out, true);
  for (double v : mine) EXPECT_NEAR(v, 1.0, 2e-3);
  // The shape of D65: value(λ) / value(560 nm) as in the CSV.
  const auto d65 = read_data("cie/cie_illuminant_d65.csv");
  const double at560 = out["values"][40].get<double>();
  for (size_t i = 0; i < 95; i += 10)
    EXPECT_NEAR(out["values"][i].get<double>() / at560, lerp_rows(d65, 360.0 + 5.0 * double(i)) / lerp_rows(d65, 560), 1e-4);
}

TEST(CliSpectrum, BrightColouredEmission) {
  const json out = run_one({"spectrum", "--rgb", "8", "2", "0.5", "--emission"});
  const auto rgb = color3(out["rgb"]);
  const std::array<double, 3> in{8, 2, 0.5};
  for (size_t c = 0; c < 3; ++c) EXPECT_NEAR(rgb[c] / 8, in[c] / 8, 2e-3);
}

TEST(CliSpectrum, BadInputIsRefused) {
  expect_bad_input(run_gonio({"spectrum", "--rgb", "1.5", "0", "0"}), {"--rgb", "R", "[0, 1]", "1.5"});
  expect_bad_input(run_gonio({"spectrum", "--rgb", "0", "-0.1", "0", "--emission"}), {"--rgb", "G"});
  expect_bad_input(run_gonio({"spectrum", "--rgb", "0", "0", "nan"}), {"--rgb"});
  expect_bad_input(run_gonio({"spectrum", "--rgb", "0", "0", "inf", "--emission"}), {"--rgb"});
  expect_bad_input(run_gonio({"spectrum", "--rgb", "0.5", "0.5"}), {"--rgb"});
  expect_bad_input(run_gonio({"spectrum", "--rgb", "abc", "0", "0"}), {"--rgb"});
  expect_bad_input(run_gonio({"spectrum"}), {"--rgb"});
}


// SPEC §2: a colour parameter given as a spectrum. RGB mode reduces a reflectance to its
// colour under D65 (this file's srgb_of), clamped to [0, 1] outside the sRGB gamut.
TEST(CliSpectrumParams, ReflectanceSpectrumIsItsColourUnderD65) {
  // A smooth ramp (inside the gamut) and a step at 600 nm (outside: green and blue < 0).
  const std::vector<std::vector<std::array<double, 2>>> spectra = {
      {{360, 0.2}, {830, 0.8}}, {{360, 0}, {599, 0}, {600, 1}, {830, 1}}};
  for (const auto& pts : spectra) {
    json points = json::array(), printed{{"lambda", json::array()}, {"values", json::array()}};
    for (const auto& p : pts) points.push_back({p[0], p[1]});
    for (int nm = 360; nm <= 830; ++nm) {  // the same spectrum at 1 nm for srgb_of
      double v = pts.back()[1];
      for (size_t i = 0; i + 1 < pts.size(); ++i)
        if (pts[i][0] <= nm && nm <= pts[i + 1][0])
          v = pts[i][1] + (nm - pts[i][0]) / (pts[i + 1][0] - pts[i][0]) * (pts[i + 1][1] - pts[i][1]);
      printed["lambda"].push_back(nm);
      printed["values"].push_back(v);
    }
    const json bsdf{{"type", "diffuse"}, {"reflectance", {{"spectrum", points}}}};
    const json out = run_one({"eval", "--bsdf", bsdf.dump()}, "0 0 1 0 0 1\n");
    const auto f = color3(out["f"]);
    const auto expect = srgb_of(printed, false);
    for (size_t c = 0; c < 3; ++c)
      EXPECT_NEAR(f[c] * M_PI, std::clamp(expect[c], 0.0, 1.0), 1e-3) << bsdf.dump() << " channel " << c;
  }
}

// A dielectric's eta as a named glass or a Sellmeier formula: RGB mode reads it at 550 nm.
// n(λ)² = 1 + Σ B λ² / (λ² − C), λ in µm (Schott's N-BK7 catalogue coefficients, typed here).
TEST(CliSpectrumParams, GlassIndexIsReadAt550nm) {
  const double B[3] = {1.03961212, 0.231792344, 1.01046945}, C[3] = {0.00600069867, 0.0200179144, 103.560653};
  const double l2 = 0.55 * 0.55;
  double n2 = 1;
  for (int i = 0; i < 3; ++i) n2 += B[i] * l2 / (l2 - C[i]);
  const double n = std::sqrt(n2), r0 = (n - 1) * (n - 1) / ((n + 1) * (n + 1));
  const json sellmeier{{"type", "dielectric"}, {"eta", {{"sellmeier", {{"B", B}, {"C", C}}}}}};
  for (const json& bsdf : {json{{"type", "dielectric"}, {"eta", "BK7"}}, sellmeier}) {
    const json out = run_one({"albedo", "--theta", "0", "--bsdf", bsdf.dump()});
    for (double r : color3(out["reflectance"])) EXPECT_NEAR(r, r0, 2e-6) << bsdf.dump();
  }
  expect_bad_input(run_gonio({"albedo", "--theta", "0", "--bsdf", R"({"type":"dielectric","eta":"BK8"})"}),
                   {"eta", "BK8", "BK7"});
}

// A conductor's eta and k as spectra: the channels take their values at 650, 550, 450 nm.
TEST(CliSpectrumParams, ConductorIndexSpectraAreReadPerChannel) {
  const std::string wo_wi = "0.3 0.1 0.9 -0.2 0.4 0.8\n";
  const json spectral = run_one(
      {"eval", "--bsdf",
       R"({"type":"roughconductor","alpha":0.3,"eta":{"spectrum":[[400,0.3],[700,0.9]]},"k":{"spectrum":[[400,4],[700,1]]}})"},
      wo_wi);
  // Linear in λ: eta(650, 550, 450) = 0.8, 0.6, 0.4; k = 1.5, 2.5, 3.5.
  const json rgb = run_one(
      {"eval", "--bsdf", R"({"type":"roughconductor","alpha":0.3,"eta":[0.8,0.6,0.4],"k":[1.5,2.5,3.5]})"}, wo_wi);
  const auto a = color3(spectral["f"]), b = color3(rgb["f"]);
  for (size_t c = 0; c < 3; ++c) EXPECT_NEAR(a[c], b[c], 1e-6 * b[c]) << c;
  EXPECT_NE(a[0], a[2]);
  expect_bad_input(run_gonio({"eval", "--bsdf", R"({"type":"diffuse","reflectance":{"spectrum":[[400,0.5],[700,1.5]]}})"},
                             wo_wi),
                   {"reflectance", "1.5"});
  // A spectrum file's errors name the field as well as the file.
  expect_bad_input(run_gonio({"eval", "--bsdf", R"({"type":"diffuse","reflectance":{"spectrum":"no-such-file.csv"}})"},
                             wo_wi),
                   {"diffuse: reflectance: ", "no-such-file.csv"});
}

}  // namespace
}  // namespace gonio_cli_test
