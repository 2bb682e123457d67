// gonio spectrum (SPEC §3): the printed spectrum checked against data/'s CIE tables by this
// file's own quadrature and the IEC 61966-2-1 matrix written out here, and the error
// contract for bad --rgb values.

#include <array>
#include <cmath>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "run_gonio.h"

namespace gonio_cli_test {
namespace {

std::vector<std::vector<double>> read_data(const std::string& rel) {
  std::ifstream in(std::string(GONIO_SOURCE_DIR) + "/data/" + rel);
  EXPECT_TRUE(in.good()) << rel;
  std::vector<std::vector<double>> rows;
  std::string line;
  while (std::getline(in, line)) {
    if (line.empty() || !std::isdigit(static_cast<unsigned char>(line[0]))) continue;
    std::vector<double> r;
    std::stringstream ss(line);
    std::string f;
    while (std::getline(ss, f, ',')) r.push_back(std::stod(f));
    rows.push_back(r);
  }
  return rows;
}

// Linear interpolation in rows (x = column 0, y = column `col`).
double lerp_rows(const std::vector<std::vector<double>>& rows, double x, size_t col = 1) {
  for (size_t i = 0; i + 1 < rows.size(); ++i)
    if (rows[i][0] <= x && x <= rows[i + 1][0])
      return rows[i][col] + (x - rows[i][0]) / (rows[i + 1][0] - rows[i][0]) * (rows[i + 1][col] - rows[i][col]);
  return 0;
}

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

}  // namespace
}  // namespace gonio_cli_test
