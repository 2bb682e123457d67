// The renderer against what must hold: the lecture's linearity experiment, the white
// furnace, closed forms for a point light and a rectangular area light, and determinism.

#include <cmath>
#include <filesystem>
#include <fstream>
#include <string>

#include <gtest/gtest.h>

#include "render_test_util.h"

namespace gonio::render::test {
namespace {

std::string camera_down(int size, double height) {
  // Looking straight down at the plane y = 0 from `height`, 40° field of view.
  return R"("camera": {"position": [0, )" + std::to_string(height) +
         R"(, 0], "look_at": [0, 0, 0], "up": [0, 0, -1], "fov": 40, "width": )" + std::to_string(size) +
         R"(, "height": )" + std::to_string(size) + "}";
}

// Lecture §2: radiance is linear in the light sources. Each light alone (the others
// switched off, their bodies still in place) summed over the lights must equal all lights
// together, within the noise measured by rendering with two seeds.
TEST(Render, LinearityInTheLights) {
  const std::string on[] = {
      R"({"type": "point", "position": [1, 2, 1], "intensity": [3, 2, 1]})",
      R"({"type": "quad", "corner": [-2.5, 2, -0.5], "edge1": [1, 0, 0], "edge2": [0, 0, 1], "radiance": [1, 2, 3]})",
      R"({"type": "sphere", "center": [-1.5, 1.5, 0.5], "radius": 0.3, "radiance": 4})",
      R"(0.2, 0.3, 0.4)",
  };
  const std::string off[] = {
      R"({"type": "point", "position": [1, 2, 1], "intensity": 0})",
      R"({"type": "quad", "corner": [-2.5, 2, -0.5], "edge1": [1, 0, 0], "edge2": [0, 0, 1], "radiance": 0})",
      R"({"type": "sphere", "center": [-1.5, 1.5, 0.5], "radius": 0.3, "radiance": 0})",
      R"(0, 0, 0)",
  };
  // Light k switched on (k = -1: all of them); the environment is light 3.
  auto scene = [&](int k, int seed) {
    auto pick = [&](int i) { return k == -1 || k == i ? on[i] : off[i]; };
    return "{" + camera_down(32, 3) + R"(, "render": {"spp": 64, "seed": )" + std::to_string(seed) +
           R"(}, "shapes": [
      {"type": "quad", "corner": [-5, 0, -5], "edge1": [0, 0, 10], "edge2": [10, 0, 0], "material": {"type": "roughconductor", "material": "Cu", "alpha": 0.3}},
      {"type": "sphere", "center": [0.3, 0.5, 0], "radius": 0.5, "material": {"type": "plastic", "reflectance": [0.6, 0.3, 0.2], "alpha": 0.2}}],
      "lights": [)" + pick(0) + "," + pick(1) + "," + pick(2) + R"(], "environment": {"radiance": [)" + pick(3) + "]}}";
  };
  const Image all = render_text(scene(-1, 1));
  const Image all2 = render_text(scene(-1, 2));
  Image sum(32, 32);
  for (int k = 0; k < 4; ++k) {
    const Image part = render_text(scene(k, 10 + k));
    for (int y = 0; y < 32; ++y)
      for (int x = 0; x < 32; ++x) sum.at(x, y) += part.at(x, y);
  }
  // The lights lie outside the camera's view: only their light differs between images.
  // Compare 8×8 blocks; the noise of a block is estimated from the two seeds of `all`.
  for (int by = 0; by < 32; by += 8) {
    for (int bx = 0; bx < 32; bx += 8) {
      for (int c = 0; c < 3; ++c) {
        const double a = block_mean(all, bx, by, 8, c), a2 = block_mean(all2, bx, by, 8, c);
        const double s = block_mean(sum, bx, by, 8, c);
        // |a − a2| estimates √2·σ; sum has up to four independent parts (≈ 2σ).
        const double sigma = std::abs(a - a2) / std::sqrt(2.0) + 0.01 * a;
        EXPECT_NEAR(s, a, 6 * sigma + 1e-6) << "block " << bx << "," << by << " channel " << c;
      }
    }
  }
}

// White furnace: a white Lambertian sphere inside a uniform environment of radiance 1.
// Every path ends in the environment with throughput 1, so every pixel is 1.
TEST(Render, WhiteFurnaceDiffuse) {
  const Image img = render_text(R"({"camera": {"position": [0, 0, 3], "look_at": [0, 0, 0], "fov": 45, "width": 24, "height": 24},
    "render": {"spp": 128, "max_depth": 64},
    "shapes": [{"type": "sphere", "center": [0, 0, 0], "radius": 1, "material": {"type": "diffuse", "reflectance": 1}}],
    "environment": {"radiance": 1}})");
  // The sphere covers the central ±10 pixels; the 12×12 block in the middle is all sphere
  // (4608 samples of standard deviation ≈ 0.5: σ of the mean ≈ 0.0075).
  for (int c = 0; c < 3; ++c) EXPECT_NEAR(block_mean(img, 6, 6, 12, c), 1.0, 0.03);
  for (int c = 0; c < 3; ++c) EXPECT_NEAR(block_mean(img, 0, 0, 24, c), 1.0, 0.02);
}

// The same with an F = 1 rough conductor with multiple-scattering compensation: its
// albedo is within [0.998, 1] (docs/microfacet.md), so the sphere renders to ~1.
TEST(Render, WhiteFurnaceRoughConductorMultiscatter) {
  const Image img = render_text(R"({"camera": {"position": [0, 0, 3], "look_at": [0, 0, 0], "fov": 40, "width": 24, "height": 24},
    "render": {"spp": 128, "max_depth": 64},
    "shapes": [{"type": "sphere", "center": [0, 0, 0], "radius": 1, "material": {"type": "roughconductor", "fresnel": "schlick", "f0": 1, "alpha": 1, "multiscatter": true}}],
    "environment": {"radiance": 1}})");
  // The central 12×12 pixels all see the sphere.
  for (int c = 0; c < 3; ++c) EXPECT_NEAR(block_mean(img, 6, 6, 12, c), 1.0, 0.03);
}

// Lecture eq. 2 with one point light over a Lambertian plane:
// L = ρ/π · I · cos θ / r², no noise apart from the pixel's footprint.
TEST(Render, PointLightOverDiffusePlaneMatchesClosedForm) {
  const double rho = 0.6, I = 5, h = 1.5, lx = 0.4, lz = -0.3, cam = 3;
  const Image img = render_text("{" + camera_down(64, cam) + R"(, "render": {"spp": 256},
    "shapes": [{"type": "quad", "corner": [-5, 0, -5], "edge1": [0, 0, 10], "edge2": [10, 0, 0], "material": {"type": "diffuse", "reflectance": 0.6}}],
    "lights": [{"type": "point", "position": [0.4, 1.5, -0.3], "intensity": 5}]})");
  const double tan_half = std::tan(20 * kPiD / 180);
  // The closed form at a film point (fx, fy) in pixel units; up = −z, so image x → +x
  // and image y → +z on the plane.
  auto radiance_at = [&](double fx, double fy) {
    const double sx = (2 * fx / 64 - 1) * tan_half, sy = (1 - 2 * fy / 64) * tan_half;
    const double x = sx * cam, z = -sy * cam;
    const double dx = lx - x, dz = lz - z, r2 = dx * dx + h * h + dz * dz;
    return rho / kPiD * I * (h / std::sqrt(r2)) / r2;
  };
  for (int py : {5, 20, 32, 50}) {
    for (int px : {3, 31, 47, 60}) {
      // A pixel is the mean over its square of film (uniform jitter): integrate the
      // closed form over it with the midpoint rule on a 32×32 grid.
      double expected = 0, square = 0;
      for (int j = 0; j < 32; ++j) {
        for (int i = 0; i < 32; ++i) {
          const double v = radiance_at(px + (i + 0.5) / 32, py + (j + 0.5) / 32);
          expected += v;
          square += v * v;
        }
      }
      expected /= 32 * 32;
      // Only the jitter is random: the pixel is a mean of 256 values of the closed form
      // at uniform points of the pixel, with this standard deviation.
      const double sigma = std::sqrt(std::max(0.0, square / (32 * 32) - expected * expected) / 256);
      EXPECT_NEAR(img.at(px, py)[0], expected, 4 * sigma + 1e-5 * expected) << px << "," << py;
    }
  }
}

// A Lambertian plane under a parallel rectangular light of radiance L: at the point below
// the rectangle's centre, L_out = ρ · L · F, with F the form factor of the rectangle,
// summed over its four quarters, each with a corner above the point (Howell, "A Catalog
// of Radiation Heat Transfer Configuration Factors", C-11):
//   F = 1/(2π) [X/√(1+X²) atan(Y/√(1+X²)) + Y/√(1+Y²) atan(X/√(1+Y²))], X = a/h, Y = b/h.
TEST(Render, RectangleLightOverDiffusePlaneMatchesFormFactor) {
  const double a = 0.6, b = 0.9, h = 1.0, L = 3, rho = 0.5;
  const double F = centred_rectangle_form_factor(a, b, h);
  const Image img = render_text("{" + camera_down(16, 0.5) + R"(, "render": {"spp": 1024},
    "shapes": [{"type": "quad", "corner": [-5, 0, -5], "edge1": [0, 0, 10], "edge2": [10, 0, 0], "material": {"type": "diffuse", "reflectance": 0.5}}],
    "lights": [{"type": "quad", "corner": [-0.6, 1, -0.9], "edge1": [1.2, 0, 0], "edge2": [0, 0, 1.8], "radiance": 3}]})");
  // The camera sits below the light, above the plane: the central 2×2 pixels see the
  // plane within ±0.02 of the centre, where the irradiance is flat to 1e-3.
  const double got = block_mean(img, 7, 7, 2, 1);
  EXPECT_NEAR(got, rho * L * F, 0.02 * rho * L * F);
}

// A Lambertian plane under a sphere of radiance L whose centre is at height d above the
// point: a uniform sphere acts like a point of intensity L·πr², so E = π L r²/d² as long
// as the sphere is wholly above the horizon (Howell, factor B-5), and L_out = ρ L r²/d².
TEST(Render, SphereLightOverDiffusePlaneMatchesClosedForm) {
  const double rho = 0.5, L = 5, r = 0.4, d = 1.2;
  const Image img = render_text("{" + camera_down(16, 0.6) + R"(, "render": {"spp": 512},
    "shapes": [{"type": "quad", "corner": [-5, 0, -5], "edge1": [0, 0, 10], "edge2": [10, 0, 0], "material": {"type": "diffuse", "reflectance": 0.5}}],
    "lights": [{"type": "sphere", "center": [0, 1.2, 0], "radius": 0.4, "radiance": 5}]})");
  const double expected = rho * L * r * r / (d * d);
  EXPECT_NEAR(block_mean(img, 7, 7, 2, 0), expected, 0.02 * expected);
}

// A Lambertian plane under a lat-long environment map: the irradiance is the sum over the
// map's pixels of L · ∫ cos θ dω over the part of each pixel above the plane, in closed
// form (2π/W) · (sin²θ1 − sin²θ0)/2 per pixel of rows θ0..θ1. Exercises the map's
// importance sampling and its MIS with BSDF sampling.
TEST(Render, EnvironmentMapOverDiffusePlaneMatchesIrradiance) {
  const int W = 16, H = 8;
  Image map(W, H);
  for (int y = 0; y < H; ++y)
    for (int x = 0; x < W; ++x) map.at(x, y) = Color(Float(0.2 + 0.1 * x), Float(0.5), Float(0.05 * y));
  map.at(5, 1) = Color(40, 30, 20);  // a small bright "sun"
  map.at(12, 3) = Color(0, 0, 0);
  const std::string path = (std::filesystem::temp_directory_path() / "gonio_test_env.exr").string();
  write_exr(map, path);
  const double rho = 0.5;
  double expected[3] = {0, 0, 0};
  for (int y = 0; y < H / 2; ++y) {  // rows below the horizon do not reach the plane
    const double s0 = std::sin(kPiD * y / H), s1 = std::sin(kPiD * (y + 1) / H);
    const double cos_integral = 2 * kPiD / W * (s1 * s1 - s0 * s0) / 2;
    for (int x = 0; x < W; ++x)
      for (int c = 0; c < 3; ++c) expected[c] += rho / kPiD * map.at(x, y)[c] * cos_integral;
  }
  const Image img = render_text("{" + camera_down(8, 1) + R"(, "render": {"spp": 512},
    "shapes": [{"type": "quad", "corner": [-50, 0, -50], "edge1": [0, 0, 100], "edge2": [100, 0, 0], "material": {"type": "diffuse", "reflectance": 0.5}}],
    "environment": {"file": ")" + path + R"("}})");
  std::filesystem::remove(path);
  for (int c = 0; c < 3; ++c) EXPECT_NEAR(block_mean(img, 0, 0, 8, c), expected[c], 0.01 * expected[c] + 1e-4) << c;
}

// Shading normals far from the geometric one (lecture §3.2: N comes from the mesh, not
// the facet) must neither let light through an opaque surface nor blacken pixels.
TEST(Render, ShadingNormalsNeitherLeakNorBlacken) {
  const auto dir = std::filesystem::temp_directory_path() / "gonio_test_normals";
  std::filesystem::create_directories(dir);
  {
    // A square in the plane y = 0 whose vertex normals lean 70° away from +y, in
    // different directions, so that the interpolated normal swings across the facet.
    std::ofstream obj(dir / "tilted.obj");
    obj << "v -2 0 -2\nv 2 0 -2\nv 2 0 2\nv -2 0 2\n"
           "vn 0.94 0.342 0\nvn 0 0.342 0.94\nvn -0.94 0.342 0\nvn 0 0.342 -0.94\n"
           "f 1//1 4//4 3//3\nf 1//1 3//3 2//2\n";
  }
  const std::string obj = (dir / "tilted.obj").string();
  // (1) A point light under the surface, the camera above it: nothing may arrive.
  for (const char* material : {R"({"type": "diffuse", "reflectance": 1})",
                               R"({"type": "roughconductor", "material": "Ag", "alpha": 0.3})",
                               R"({"type": "plastic", "reflectance": 0.8})"}) {
    const Image dark = render_text("{" + camera_down(16, 1) + R"(, "render": {"spp": 16},
      "shapes": [{"type": "mesh", "file": ")" + obj + R"(", "material": )" + material + R"(}],
      "lights": [{"type": "point", "position": [0.2, -0.5, 0.1], "intensity": 100}]})");
    for (const Color& c : dark.pixels()) ASSERT_EQ(c.max_component(), 0) << material;
  }
  // (2) A white diffuse surface under a uniform sky: every pixel sees light. With
  // shading normals it need not be exactly 1, but no pixel may be black or far off.
  const Image lit = render_text("{" + camera_down(16, 1) + R"(, "render": {"spp": 64},
      "shapes": [{"type": "mesh", "file": ")" + obj + R"(", "material": {"type": "diffuse", "reflectance": 1}}],
      "environment": {"radiance": 1}})");
  for (const Color& c : lit.pixels()) {
    ASSERT_GT(c.min_component(), 0.3);
    ASSERT_LT(c.max_component(), 2.0);
  }
  std::filesystem::remove_all(dir);
}

TEST(Render, SameImageWhateverTheThreadCount) {
  const std::string scene = std::string(default_scene_json());
  Scene s = parse_scene(scene, "default", "");
  s.camera.width = 48;
  s.camera.height = 27;
  s.settings.spp = 4;
  RenderOptions one, two;
  one.threads = 1;
  two.threads = 2;
  const Image a = render(s, one), b = render(s, two);
  for (int y = 0; y < 27; ++y)
    for (int x = 0; x < 48; ++x)
      for (int c = 0; c < 3; ++c) ASSERT_EQ(a.at(x, y)[c], b.at(x, y)[c]) << x << "," << y;
}

TEST(Render, DefaultSceneHasEveryModelFamilyAndFinitePixels) {
  Scene s = parse_scene(default_scene_json(), "default", "");
  EXPECT_EQ(s.spheres.size(), 8u);
  s.camera.width = 32;
  s.camera.height = 18;
  s.settings.spp = 2;
  const Image img = render(s, {});
  for (const Color& c : img.pixels()) {
    ASSERT_TRUE(c.is_finite());
    ASSERT_GE(c.min_component(), 0);
  }
}

}  // namespace
}  // namespace gonio::render::test
