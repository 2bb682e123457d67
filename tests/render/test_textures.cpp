// Spatially varying materials (docs/scene-format.md, "Textures"): checker and image
// textures on colour and roughness parameters, against closed forms and against the
// untextured material they equal inside each checker square.

#include <unistd.h>

#include <cmath>
#include <filesystem>
#include <functional>
#include <optional>
#include <string>

#include <gtest/gtest.h>

#include "render_test_util.h"

namespace gonio::render::test {
namespace {

constexpr double kCam = 3;   // camera height above the plane y = 0
constexpr int kSize = 64;    // image size in pixels

std::string camera_down(int size, double height) {
  return R"("camera": {"position": [0, )" + std::to_string(height) +
         R"(, 0], "look_at": [0, 0, 0], "up": [0, 0, -1], "fov": 40, "width": )" + std::to_string(size) +
         R"(, "height": )" + std::to_string(size) + "}";
}

// The plane point seen through film point (fx, fy) of the downward camera; up = −z, so
// image x → +x and image y → +z (as in test_render.cpp).
void film_to_plane(double fx, double fy, int size, double cam, double& x, double& z) {
  const double tan_half = std::tan(20 * kPiD / 180);
  x = (2 * fx / size - 1) * tan_half * cam;
  z = -(1 - 2 * fy / size) * tan_half * cam;
}

// A region of the plane over which the texture is constant, as an id; nullopt where it
// is not (near edges, where bilinear lookups blend).
using RegionOf = std::function<std::optional<long>(double x, double z)>;

// Lecture eq. 2 for a point light over a Lambertian plane of reflectance ρ(x, z):
// L = ρ/π · I · cos θ / r². Checks every pixel whose footprint lies inside one region of
// constant ρ; returns how many it checked.
int check_point_light_closed_form(const Image& img, const RegionOf& region, const std::function<Color(long)>& rho,
                                  double I, double lx, double h, double lz) {
  int checked = 0;
  for (int py = 0; py < kSize; ++py) {
    for (int px = 0; px < kSize; ++px) {
      // The pixel is the mean over its square of film (uniform jitter): the closed form
      // integrated by the midpoint rule on a 16×16 grid, and the jitter's σ for 256 spp.
      std::optional<long> id;
      bool flat = true;
      double g = 0, g2 = 0;
      constexpr int n = 16;
      for (int j = 0; j < n && flat; ++j) {
        for (int i = 0; i < n && flat; ++i) {
          double x, z;
          film_to_plane(px + (i + 0.5) / n, py + (j + 0.5) / n, kSize, kCam, x, z);
          const auto r = region(x, z);
          if (!r || (id && *id != *r)) flat = false;
          id = r;
          const double dx = lx - x, dz = lz - z, r2 = dx * dx + h * h + dz * dz;
          const double v = I / kPiD * (h / std::sqrt(r2)) / r2;
          g += v;
          g2 += v * v;
        }
      }
      if (!flat) continue;
      g /= n * n;
      const double sigma = std::sqrt(std::max(0.0, g2 / (n * n) - g * g) / 256);
      const Color r = rho(*id);
      for (int c = 0; c < 3; ++c)
        EXPECT_NEAR(img.at(px, py)[c], r[c] * g, r[c] * (4 * sigma + 1e-4 * g) + 1e-7) << px << "," << py << " channel " << c;
      ++checked;
    }
  }
  return checked;
}

// (a) A checker of two reflectances: ρ(uv) / π · I cos θ / r² inside each square.
TEST(Textures, CheckerDiffusePlaneMatchesClosedForm) {
  // The quad [-5, 5]² has u = (z + 5)/10, v = (x + 5)/10; uv_scale 20 makes squares of
  // 0.5: the square of (x, z) is (floor(2x), floor(2z)), and `a` where their sum is even.
  const Image img = render_text(std::string("{") + camera_down(kSize, kCam) + R"(, "render": {"spp": 256},
    "shapes": [{"type": "quad", "corner": [-5, 0, -5], "edge1": [0, 0, 10], "edge2": [10, 0, 0],
      "material": {"type": "diffuse", "reflectance": {"checker": [0.2, [0.9, 0.5, 0.1]], "uv_scale": [20, 20]}}}],
    "lights": [{"type": "point", "position": [0.4, 1.5, -0.3], "intensity": 5}]})");
  auto region = [](double x, double z) -> std::optional<long> {
    const double sx = 2 * x, sz = 2 * z;
    // Keep clear of the squares' edges by a little more than rounding.
    if (std::abs(sx - std::round(sx)) < 1e-3 || std::abs(sz - std::round(sz)) < 1e-3) return std::nullopt;
    return static_cast<long>(std::floor(sx) + std::floor(sz) + 100);
  };
  auto rho = [](long parity) { return parity % 2 == 0 ? Color(0.2f) : Color(0.9f, 0.5f, 0.1f); };
  const int checked = check_point_light_closed_form(img, region, rho, 5, 0.4, 1.5, -0.3);
  EXPECT_GT(checked, kSize * kSize / 2);
}

// (b) An image texture on the reflectance: each 2×2 block of texels holds one colour, so
// that the bilinear lookup is that colour between the block's texel centres; there the
// plane is ρ(texel) / π · I cos θ / r². EXR texels are linear; PNG codes are decoded as
// sRGB, the default for a colour parameter.
void image_texture_test(const std::string& extension) {
  constexpr int W = 8;
  Image tex(W, W);
  for (int y = 0; y < W; ++y)
    for (int x = 0; x < W; ++x) {
      const int bx = x / 2, by = y / 2;
      tex.at(x, y) = Color(Float(0.1 + 0.2 * bx), Float(0.8 - 0.15 * by), Float(0.05 + 0.1 * ((bx + by) % 4)));
    }
  const std::string path =
      (std::filesystem::temp_directory_path() / ("gonio_test_reflectance_" + std::to_string(::getpid()) + extension)).string();
  if (extension == ".exr") write_exr(tex, path);
  else write_png(tex, path, {0, ToneMap::Clamp});
  const Image stored = read_image(path, true);  // what the texels are after decoding
  const Image img = render_text(std::string("{") + camera_down(kSize, kCam) + R"(, "render": {"spp": 256},
    "shapes": [{"type": "quad", "corner": [-2, 0, -2], "edge1": [0, 0, 4], "edge2": [4, 0, 0],
      "material": {"type": "diffuse", "reflectance": {"texture": ")" + path + R"("}}}],
    "lights": [{"type": "point", "position": [0.4, 1.5, -0.3], "intensity": 5}]})");
  std::filesystem::remove(path);
  // u = (z + 2)/4, v = (x + 2)/4; continuous texel coordinates s = 8u − 0.5 (columns) and
  // t = 8v − 0.5 (rows from the bottom); constant where floor(s) and floor(t) are even.
  auto region = [](double x, double z) -> std::optional<long> {
    const double s = 8 * (z + 2) / 4 - 0.5, t = 8 * (x + 2) / 4 - 0.5;
    if (std::abs(s - std::round(s)) < 1e-3 || std::abs(t - std::round(t)) < 1e-3) return std::nullopt;
    const long fs = static_cast<long>(std::floor(s)), ft = static_cast<long>(std::floor(t));
    if (fs < 0 || ft < 0 || fs > 6 || ft > 6 || fs % 2 || ft % 2) return std::nullopt;
    return fs * 100 + ft;
  };
  auto rho = [&](long id) {
    const int column = static_cast<int>(id / 100), row_from_bottom = static_cast<int>(id % 100);
    return stored.at(column, W - 1 - row_from_bottom);
  };
  const int checked = check_point_light_closed_form(img, region, rho, 5, 0.4, 1.5, -0.3);
  EXPECT_GT(checked, 200);
}

TEST(Textures, ExrReflectanceMatchesClosedForm) { image_texture_test(".exr"); }
TEST(Textures, PngReflectanceIsDecodedAsSrgbAndMatchesClosedForm) { image_texture_test(".png"); }

// (c) A rough conductor whose roughness is a checker of two values renders, inside each
// square, exactly as the untextured material with that value: the model at the hit is
// the same, and so are the random numbers (one stream per pixel).
void roughness_checker_test(const std::string& textured_alpha, const std::string& alpha_a, const std::string& alpha_b) {
  auto scene = [](const std::string& alpha) {
    return std::string("{") + camera_down(kSize, kCam) + R"(, "render": {"spp": 8, "seed": 7},
      "shapes": [{"type": "quad", "corner": [-5, 0, -5], "edge1": [0, 0, 10], "edge2": [10, 0, 0],
        "material": {"type": "roughconductor", "material": "Cu", "alpha": )" + alpha + R"(}}],
      "lights": [{"type": "point", "position": [0.4, 1.5, -0.3], "intensity": 5},
                 {"type": "quad", "corner": [1, 2, -0.5], "edge1": [1, 0, 0], "edge2": [0, 0, 1], "radiance": 3}],
      "environment": {"radiance": [0.2, 0.3, 0.4]}})";
  };
  const Image textured = render_text(scene(textured_alpha));
  const Image a = render_text(scene(alpha_a)), b = render_text(scene(alpha_b));
  // uv_scale 10 on the quad [-5, 5]²: unit squares, `a` where floor(x) + floor(z) is even.
  int in_a = 0, in_b = 0, differ = 0;
  for (int py = 0; py < kSize; ++py) {
    for (int px = 0; px < kSize; ++px) {
      double x0, z0, x1, z1;
      film_to_plane(px, py, kSize, kCam, x0, z0);
      film_to_plane(px + 1, py + 1, kSize, kCam, x1, z1);
      const double m = 1e-3;  // margin
      if (std::floor(x0 - m) != std::floor(x1 + m) || std::floor(z0 - m) != std::floor(z1 + m)) continue;
      const bool even = static_cast<long>(std::floor(x0) + std::floor(z0)) % 2 == 0;
      const Image& expected = even ? a : b;
      (even ? in_a : in_b)++;
      for (int c = 0; c < 3; ++c) {
        ASSERT_EQ(textured.at(px, py)[c], expected.at(px, py)[c]) << px << "," << py << " channel " << c;
        differ += a.at(px, py)[c] != b.at(px, py)[c];
      }
    }
  }
  EXPECT_GT(in_a, 500);
  EXPECT_GT(in_b, 500);
  EXPECT_GT(differ, 500);  // the two roughnesses do look different
}

TEST(Textures, RoughnessCheckerEqualsUntexturedInEachSquare) {
  roughness_checker_test(R"({"checker": [0.05, 0.4], "uv_scale": [10, 10]})", "0.05", "0.4");
}

TEST(Textures, AnisotropicRoughnessEntryCheckerEqualsUntexturedInEachSquare) {
  roughness_checker_test(R"([{"checker": [0.05, 0.4], "uv_scale": 10}, 0.2])", "[0.05, 0.2]", "[0.4, 0.2]");
}

// A textured material keeps the untextured path for materials without textures, and the
// textures of a material stay attached to it.
TEST(Textures, LoaderAttachesTexturesOnlyWhereGiven) {
  const Scene s = parse_scene(R"({"materials": {
      "plain": {"type": "ward", "kd": 0.3, "ks": 0.2, "alpha": 0.1},
      "wood": {"type": "ward", "kd": {"checker": [0.1, 0.5]}, "ks": 0.2, "alpha": [0.1, {"checker": [0.2, 0.3]}]}},
    "shapes": [{"type": "sphere", "center": [0, 0, 0], "radius": 1, "material": "plain"},
               {"type": "sphere", "center": [0, 3, 0], "radius": 1, "material": "wood"}]})",
                              "test", "");
  ASSERT_EQ(s.materials.size(), 2u);
  EXPECT_TRUE(s.materials[0].textures.empty());
  ASSERT_EQ(s.materials[1].textures.size(), 2u);
  // (JSON objects are read in key order: alpha, then kd.)
  EXPECT_EQ(s.materials[1].textures[0].param, MaterialParam::AlphaY);
  EXPECT_EQ(s.materials[1].textures[1].param, MaterialParam::Kd);
  std::optional<BxDF> scratch;
  EXPECT_EQ(&s.materials[0].at({0.3f, 0.7f}, scratch), &s.materials[0].bxdf);
  EXPECT_FALSE(scratch.has_value());
  const BxDF& m = s.materials[1].at({0.5f, 0.5f}, scratch);  // floor(0.5) + floor(0.5) = 0: a
  const auto* ward = std::get_if<WardBxDF>(&m.models());
  ASSERT_NE(ward, nullptr);
  EXPECT_EQ(ward->kd, Color(0.1f));
  EXPECT_EQ(ward->alpha_x, 0.1f);
  EXPECT_EQ(ward->alpha_y, 0.2f);
  const BxDF& m2 = s.materials[1].at({1.5f, 0.5f}, scratch);  // odd: b
  EXPECT_EQ(std::get<WardBxDF>(m2.models()).kd, Color(0.5f));
  EXPECT_EQ(std::get<WardBxDF>(m2.models()).alpha_y, 0.3f);
}

}  // namespace
}  // namespace gonio::render::test
