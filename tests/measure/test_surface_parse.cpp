// parse_surface (include/gonio/measure/surface.h): every type parses, every bad field is
// one InputError line that names it.
#include <gtest/gtest.h>

#include <cmath>
#include <string>
#include <vector>

#include "gonio/error.h"
#include "gonio/measure/surface.h"

namespace gm = gonio::measure;

namespace {

// The message of the InputError that parsing `json` throws ("" when none is thrown).
[[maybe_unused]] std::string error_of(const std::string& json, const std::string& base_dir = "") {
  try {
    gm::parse_surface(json, "--surface", base_dir);
  } catch (const gonio::InputError& e) {
    return e.what();
  }
  return "";
}

constexpr const char* kWhite = R"("material": {"type": "mirror"})";

}  // namespace

TEST(SurfaceParse, FlatIsOneCellOfHeightZero) {
  const gm::Surface s = gm::parse_surface(std::string(R"({"type": "flat", )") + kWhite + "}");
  EXPECT_EQ(s.type, "flat");
  ASSERT_EQ(s.field.n, 1);
  ASSERT_EQ(s.field.z.size(), 1u);
  EXPECT_EQ(s.field.z[0], 0.0f);
  EXPECT_EQ(s.field.size, 1.0);
}

TEST(SurfaceParse, GaussianDefaults) {
  const gm::Surface s =
      gm::parse_surface(std::string(R"({"type": "gaussian", "alpha": 0.3, "resolution": 64, )") + kWhite + "}");
  EXPECT_EQ(s.type, "gaussian");
  EXPECT_EQ(s.field.n, 64);
  EXPECT_EQ(s.field.z.size(), 64u * 64u);
}

// Every bad field: one InputError line that names the type and the field, with the value.
TEST(SurfaceParse, BadFieldsAreNamed) {
  const std::string m = kWhite;
  struct Case {
    std::string json;
    std::vector<std::string> needles;
  };
  const std::vector<Case> cases = {
      {"[]", {"surface must be a JSON object"}},
      {"{" + m + "}", {"surface", "type"}},
      {R"({"type": 3, )" + m + "}", {"type must be a string"}},
      {R"({"type": "fractal", )" + m + "}", {"unknown type", "fractal"}},
      {R"({"type": "flat"})", {"flat: missing field 'material'"}},
      {R"({"type": "flat", "alpha": 0.3, )" + m + "}", {"flat: unknown field 'alpha'"}},
      {R"({"type": "flat", "size": 0, )" + m + "}", {"flat: size must be in (0, ", "got 0"}},
      {R"({"type": "flat", "material": {"type": "roughconductor", "alpha": -1}})", {"flat: material", "alpha"}},
      {R"({"type": "gaussian", )" + m + "}", {"gaussian: missing field 'alpha'"}},
      {R"({"type": "gaussian", "alpha": -1, )" + m + "}", {"gaussian: alpha must be in (0, 2], got -1"}},
      {R"({"type": "gaussian", "alpha": 2.5, )" + m + "}", {"gaussian: alpha must be in (0, 2], got 2.5"}},
      {R"({"type": "gaussian", "alpha": [0.1, 0], )" + m + "}", {"gaussian: alpha must be in (0, 2], got 0"}},
      {R"({"type": "gaussian", "alpha": [0.1], )" + m + "}", {"gaussian: alpha must be a number or [alpha_x, alpha_y]"}},
      {R"({"type": "gaussian", "alpha": "rough", )" + m + "}", {"gaussian: alpha must be a number"}},
      {R"({"type": "gaussian", "alpha": 0.3, "resolution": 8, )" + m + "}", {"gaussian: resolution must be in [16, 2048], got 8"}},
      {R"({"type": "gaussian", "alpha": 0.3, "resolution": 4096, )" + m + "}", {"gaussian: resolution", "got 4096"}},
      {R"({"type": "gaussian", "alpha": 0.3, "resolution": 100.5, )" + m + "}", {"gaussian: resolution must be an integer"}},
      {R"({"type": "gaussian", "alpha": 0.3, "resolution": 64, "correlation": 0.01, )" + m + "}",
       {"gaussian: correlation must be in [0.03125, 0.5]", "got 0.01"}},
      {R"({"type": "gaussian", "alpha": 0.3, "correlation": 0.6, )" + m + "}", {"gaussian: correlation", "got 0.6"}},
      {R"({"type": "gaussian", "alpha": [0.01, 2], )" + m + "}", {"gaussian: alpha [0.01, 2] makes the correlation length along y"}},
      {R"({"type": "gaussian", "alpha": [2, 0.01], "correlation": 0.1, "resolution": 2048, )" + m + "}",
       {"gaussian: alpha [2, 0.01] makes the correlation length along y 1.41"}},
      {R"({"type": "gaussian", "alpha": 0.3, "seed": -1, )" + m + "}", {"gaussian: seed must be in [0, ", "got -1"}},
      {R"({"type": "gaussian", "alpha": 0.3, "seed": "x", )" + m + "}", {"gaussian: seed must be an integer"}},
      {R"({"type": "gaussian", "alpha": 0.3, "size": -2, )" + m + "}", {"gaussian: size", "got -2"}},
      {R"({"type": "gaussian", "alpha": 0.3, "angle": 30, )" + m + "}", {"gaussian: unknown field 'angle'"}},
      {R"({"type": "gaussian", "alpha": 0.3, "material": {"type": "plaster"}})", {"gaussian: material", "plaster"}},
      {R"({"type": "vgroove", )" + m + "}", {"vgroove: missing field 'angle'"}},
      {R"({"type": "vgroove", "angle": 90, )" + m + "}", {"vgroove: angle must be in (0, 90), got 90"}},
      {R"({"type": "vgroove", "angle": 0, )" + m + "}", {"vgroove: angle must be in (0, 90), got 0"}},
      {R"({"type": "vgroove", "angle": 30, "grooves": 0, )" + m + "}", {"vgroove: grooves must be in [1, 1024], got 0"}},
      {R"({"type": "vgroove", "angle": 30, "grooves": 2000, )" + m + "}", {"vgroove: grooves", "got 2000"}},
      {R"({"type": "image", "height": 1, )" + m + "}", {"image: missing field 'file'"}},
      {R"({"type": "image", "file": 3, "height": 1, )" + m + "}", {"image: file must be a string"}},
      {R"({"type": "image", "file": "h.png", )" + m + "}", {"image: missing field 'height'"}},
      {R"({"type": "image", "file": "h.png", "height": -1, )" + m + "}", {"image: height must be in [0, 1000], got -1"}},
      {R"({"type": "image", "file": "/nonexistent/h.png", "height": 1, )" + m + "}", {"image: ", "/nonexistent/h.png"}},
      {R"({"type": "flat", )", {"--surface", "malformed JSON"}},
  };
  for (const Case& c : cases) {
    const std::string e = error_of(c.json);
    ASSERT_FALSE(e.empty()) << "no error for " << c.json;
    EXPECT_EQ(e.find('\n'), std::string::npos) << e;
    for (const auto& needle : c.needles) EXPECT_NE(e.find(needle), std::string::npos) << "'" << needle << "' not in: " << e;
  }
}

TEST(SurfaceParse, GaussianFieldsReachTheGenerator) {
  const gm::Surface a = gm::parse_surface(
      std::string(R"({"type": "gaussian", "alpha": [0.2, 0.4], "resolution": 32, "correlation": 0.125, "size": 3, "seed": 9, )") +
      kWhite + "}");
  EXPECT_EQ(a.field.n, 32);
  EXPECT_EQ(a.field.size, 3.0);
  // The RMS forward-difference slope per axis (heightfield.h) is α/√2 per axis.
  double sx = 0, sy = 0;
  const double h = a.field.spacing();
  for (int j = 0; j < 32; ++j)
    for (int i = 0; i < 32; ++i) {
      const double dx = (a.field.at(i + 1, j) - a.field.at(i, j)) / h, dy = (a.field.at(i, j + 1) - a.field.at(i, j)) / h;
      sx += dx * dx;
      sy += dy * dy;
    }
  EXPECT_NEAR(std::sqrt(sx / 1024), 0.2 / std::sqrt(2.0), 1e-4);
  EXPECT_NEAR(std::sqrt(sy / 1024), 0.4 / std::sqrt(2.0), 1e-4);
  const gm::Surface b = gm::parse_surface(
      std::string(R"({"type": "gaussian", "alpha": [0.2, 0.4], "resolution": 32, "correlation": 0.125, "size": 3, "seed": 10, )") +
      kWhite + "}");
  EXPECT_NE(a.field.z, b.field.z) << "the seed reaches the generator";
}
