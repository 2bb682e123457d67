// Spectral rendering (issue 11, item 7) against expectations made here: the white furnace
// (a closed surface of albedo 1 in a uniform environment returns the environment's
// radiance), grey scenes that must render as in RGB mode, and the hero-wavelength
// estimator against XYZ integrated by this file's own quadrature of data/cie/*.csv.
// Tolerances come from the noise measured in the images themselves (standard error of a
// mean of pixels).

#include <algorithm>
#include <array>
#include <cmath>
#include <functional>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "../data_csv.h"
#include "../unit/test_scale.h"
#include "gonio/render/image.h"
#include "gonio/spectrum/rgb_to_spectrum.h"
#include "render_test_util.h"
#include "scratch_dir.h"

namespace gonio::render::test {
namespace {

using gonio_test_data::lerp_rows;
using gonio_test_data::read_data;

// XYZ of a spectral radiance L(λ) as the film defines it (cie.h): XYZ =
// ∫ L (x̄, ȳ, z̄) dλ / ∫ ȳ dλ over 360–830 nm, by composite Simpson (h = 0.25 nm) on the CSV
// observer interpolated linearly.
std::array<double, 3> xyz_of_radiance(const std::function<double(double)>& L) {
  static const auto cmf = read_data("cie/cie1931_2deg_cmf.csv");
  const double a = 360, b = 830, h = 0.25;
  const int steps = int((b - a) / h);
  double xyz[3] = {0, 0, 0}, ybar = 0;
  for (int i = 0; i <= steps; ++i) {
    const double l = a + i * h;
    const double wgt = (i == 0 || i == steps) ? 1 : (i % 2 ? 4 : 2);
    const double v = L(l);
    for (int j = 0; j < 3; ++j) xyz[j] += wgt * v * lerp_rows(cmf, l, size_t(j) + 1);
    ybar += wgt * lerp_rows(cmf, l, 2);
  }
  return {xyz[0] / ybar, xyz[1] / ybar, xyz[2] / ybar};
}

// XYZ → linear sRGB by IEC 61966-2-1:1999 eq. 5.2.
std::array<double, 3> srgb_of_radiance(const std::function<double(double)>& L) {
  const auto xyz = xyz_of_radiance(L);
  const double m[3][3] = {{3.2406, -1.5372, -0.4986}, {-0.9689, 1.8758, 0.0415}, {0.0557, -0.2040, 1.0570}};
  std::array<double, 3> rgb{};
  for (int j = 0; j < 3; ++j) rgb[size_t(j)] = m[j][0] * xyz[0] + m[j][1] * xyz[1] + m[j][2] * xyz[2];
  return rgb;
}

// D65 normalised to luminance Y = 1 (what a white RGB light and {"illuminant": "D65"}
// are): its linear sRGB, from the CSV.
std::array<double, 3> d65_white() {
  const auto d65 = read_data("cie/cie_illuminant_d65.csv");
  const double y = xyz_of_radiance([&](double l) { return lerp_rows(d65, l); })[1];
  return srgb_of_radiance([&](double l) { return lerp_rows(d65, l) / y; });
}

// Mean and standard error of the mean of one channel over a block of pixels (the pixels
// taken as independent samples; pixels whose expectations differ only inflate the error).
struct Stat {
  double mean = 0, se = 0;
};
Stat block_stat(const std::vector<Image>& imgs, int x0, int y0, int w, int h, int c) {
  double s = 0, s2 = 0;
  size_t n = 0;
  for (const Image& img : imgs)
    for (int y = y0; y < y0 + h; ++y)
      for (int x = x0; x < x0 + w; ++x) {
        const double v = img.at(x, y)[c];
        s += v;
        s2 += v * v;
        ++n;
      }
  const double mean = s / double(n);
  const double var = std::max(0.0, s2 / double(n) - mean * mean);
  return {mean, std::sqrt(var / double(n - 1))};
}

int spp(int n, int floor = 8) { return int(gonio::test::scaled(std::uint64_t(n), std::uint64_t(floor))); }

std::string furnace_scene(const std::string& material, const std::string& environment, int samples, int seed = 1) {
  return R"({"camera": {"position": [0, 0, 3], "look_at": [0, 0, 0], "fov": 45, "width": 24, "height": 24},
    "render": {"spectral": true, "spp": )" + std::to_string(samples) + R"(, "max_depth": 64, "seed": )" +
         std::to_string(seed) + R"(},
    "shapes": [{"type": "sphere", "center": [0, 0, 0], "radius": 1, "material": )" + material + R"(}],
    "environment": {"radiance": )" + environment + "}}";
}

// Every pixel of a furnace sees the environment's radiance: compare the central block
// (all sphere) and the whole image with `expected`.
void expect_furnace(const Image& img, const std::array<double, 3>& expected, const std::string& what) {
  for (int c = 0; c < 3; ++c) {
    for (const auto& [x0, size] : {std::pair{6, 12}, std::pair{0, 24}}) {
      const Stat s = block_stat({img}, x0, x0, size, size, c);
      // 5 standard errors, plus 2e-3 for the film's trapezoid rule and float sums.
      EXPECT_NEAR(s.mean, expected[size_t(c)], 5 * s.se + 2e-3 * expected[size_t(c)])
          << what << ", channel " << c << ", block " << x0 << "+" << size << " (se " << s.se << ")";
      EXPECT_LT(s.se, 0.05) << what << ": too noisy to test anything";
    }
  }
}

// 1. Spectral white furnace: reflectance 1 upsampled, environment radiance 1 as an RGB
// illuminant (D65 of luminance 1): linear sRGB (1, 1, 1) — exactly D65's white as this
// file computes it from the CSV.
TEST(SpectralRender, WhiteFurnaceRgbInputs) {
  const auto white = d65_white();
  for (int c = 0; c < 3; ++c) EXPECT_NEAR(white[size_t(c)], 1.0, 2e-3);
  expect_furnace(render_text(furnace_scene(R"({"type": "diffuse", "reflectance": 1})", "1", spp(256, 64))), white,
                 "diffuse, RGB inputs");
}

// The same with spectrum inputs: a flat reflectance 1 and {"illuminant": "D65"}; then a
// flat (equal-energy) environment spectrum, whose colour is not white in sRGB.
TEST(SpectralRender, WhiteFurnaceSpectrumInputs) {
  const std::string flat = R"({"spectrum": [[360, 1], [830, 1]]})";
  expect_furnace(render_text(furnace_scene(R"({"type": "diffuse", "reflectance": )" + flat + "}",
                                           R"({"illuminant": "D65"})", spp(256, 64))),
                 d65_white(), "diffuse, flat reflectance spectrum, D65 illuminant");
  const auto e = srgb_of_radiance([](double) { return 2.0; });
  EXPECT_GT(e[0], 1.1 * e[2]);  // illuminant E is reddish next to D65
  expect_furnace(render_text(furnace_scene(R"({"type": "diffuse", "reflectance": )" + flat + "}",
                                           R"({"spectrum": [[360, 2], [830, 2]]})", spp(256, 64))),
                 e, "diffuse, flat environment spectrum of radiance 2");
}

// The same furnace lit by an environment map (a lat-long EXR whose texels are all white):
// a texel's RGB is an emission like any other, m S(rgb/m) D65 (Jakob & Hanika 2019 §5;
// pbrt-v4's RGBIlluminantSpectrum), so the image is D65's white again. The map's path in
// the renderer (lights.cpp, Environment::radiance per texel) is not the constant
// environment's; without D65 it would render the equal-energy spectrum's reddish colour.
TEST(SpectralRender, WhiteFurnaceEnvironmentMap) {
  const gonio::test::ScratchDir dir("gonio_spectral_env");
  Image map(8, 4);
  for (int y = 0; y < map.height(); ++y)
    for (int x = 0; x < map.width(); ++x) map.at(x, y) = Color(1);
  const std::string path = dir.path("white.exr");
  write_exr(map, path);
  std::string scene = furnace_scene(R"({"type": "diffuse", "reflectance": 1})", "1", spp(256, 64));
  const std::string constant = R"("environment": {"radiance": 1})";
  scene.replace(scene.find(constant), constant.size(), R"("environment": {"file": ")" + path + R"("})");
  expect_furnace(render_text(scene), d65_white(), "diffuse, white environment map");
}

// A second guard of the map's D65, independent of the furnace (no surface, no BSDF, no
// next-event estimation): the camera sees a map of one coloured texel value directly. Its
// spectrum m S(rgb/m) D65 is made to give back rgb in linear sRGB (Jakob & Hanika 2019 §5:
// the sigmoid S fits the reflectance rgb/m under D65, whose white is (1, 1, 1) here),
// so the image is the texel's colour; the texel upsampled without D65 (an equal-energy
// illuminant) would render it 10–20 % redder (issue 56).
TEST(SpectralRender, EnvironmentMapSeenDirectlyKeepsItsColour) {
  const gonio::test::ScratchDir dir("gonio_spectral_env_direct");
  const std::array<double, 3> colour = {0.7, 0.45, 0.25};
  Image map(8, 4);
  for (int y = 0; y < map.height(); ++y)
    for (int x = 0; x < map.width(); ++x) map.at(x, y) = Color(Float(colour[0]), Float(colour[1]), Float(colour[2]));
  const std::string path = dir.path("orange.exr");
  write_exr(map, path);
  const Image img = render_text(R"({"camera": {"position": [0, 0, 0], "look_at": [0, 0, -1], "fov": 60, "width": 16, "height": 16},
      "render": {"spectral": true, "spp": )" + std::to_string(spp(64)) + R"(, "seed": 3}, "shapes": [],
      "environment": {"file": ")" + path + R"("}})");
  for (int c = 0; c < 3; ++c) {
    const Stat st = block_stat({img}, 0, 0, 16, 16, c);
    // 5 standard errors, plus 1 % for the sigmoid fit's round trip.
    EXPECT_NEAR(st.mean, colour[size_t(c)], 5 * st.se + 0.01 * colour[size_t(c)]) << "channel " << c << " (se " << st.se << ")";
    EXPECT_LT(st.se, 0.02 * colour[size_t(c)]) << "too noisy to test anything";
  }
}

// A dispersive glass sphere (SF11, named glass) in the furnace: a closed non-absorbing
// dielectric returns the environment's radiance at every wavelength; refraction drops the
// secondary wavelengths (terminate_secondary) and the image must stay unbiased.
TEST(SpectralRender, DispersiveGlassFurnaceIsUnbiased) {
  expect_furnace(render_text(furnace_scene(R"({"type": "dielectric", "eta": "SF11"})", "1", spp(128, 64))), d65_white(),
                 "SF11 sphere");
  expect_furnace(render_text(furnace_scene(R"({"type": "dielectric", "eta": "BK7"})", R"({"illuminant": "D65"})", spp(128, 64))),
                 d65_white(), "BK7 sphere");
}

// 2. A scene of grey materials and grey lights renders the same in RGB and in spectral
// mode: every grey colour upsamples to a flat spectrum, every grey light to D65 of the
// same luminance, whose sRGB is white.
TEST(SpectralRender, GreySceneMatchesRgbMode) {
  auto scene = [](bool spectral, int seed) {
    return std::string(R"({"camera": {"position": [0, 3, 0], "look_at": [0, 0, 0], "up": [0, 0, -1], "fov": 40, "width": 32, "height": 32},
      "render": {"spp": )") + std::to_string(spp(64)) + R"(, "seed": )" + std::to_string(seed) + R"(, "spectral": )" +
           (spectral ? "true" : "false") + R"(},
      "shapes": [
        {"type": "quad", "corner": [-5, 0, -5], "edge1": [0, 0, 10], "edge2": [10, 0, 0], "material": {"type": "diffuse", "reflectance": 0.5}},
        {"type": "sphere", "center": [-0.5, 0.35, 0.2], "radius": 0.35, "material": {"type": "roughconductor", "alpha": 0.3, "eta": 0.4, "k": 3}},
        {"type": "sphere", "center": [0.5, 0.35, -0.2], "radius": 0.35, "material": {"type": "dielectric", "eta": 1.5}},
        {"type": "sphere", "center": [0.1, 0.2, 0.6], "radius": 0.2, "material": {"type": "plastic", "reflectance": 0.7, "alpha": 0.2}},
        {"type": "sphere", "center": [-0.3, 0.25, -0.6], "radius": 0.25, "material": {"type": "roughdielectric", "alpha": 0.3, "eta": 1.5}}],
      "lights": [{"type": "quad", "corner": [1.5, 2, -0.5], "edge1": [1, 0, 0], "edge2": [0, 0, 1], "radiance": 4},
                 {"type": "point", "position": [-1, 2, 1], "intensity": 2}],
      "environment": {"radiance": 0.3}})";
  };
  const Image rgb = render_text(scene(false, 3));
  const Image spec = render_text(scene(true, 4));
  int blocks = 0;
  for (int by = 0; by < 32; by += 8) {
    for (int bx = 0; bx < 32; bx += 8) {
      for (int c = 0; c < 3; ++c) {
        const Stat a = block_stat({rgb}, bx, by, 8, 8, c), b = block_stat({spec}, bx, by, 8, 8, c);
        const double sigma = std::sqrt(a.se * a.se + b.se * b.se);
        EXPECT_NEAR(b.mean, a.mean, 5 * sigma + 3e-3 * a.mean) << "block " << bx << "," << by << " channel " << c;
        ++blocks;
      }
    }
  }
  // The whole image: 16 blocks' means together.
  for (int c = 0; c < 3; ++c) {
    const Stat a = block_stat({rgb}, 0, 0, 32, 32, c), b = block_stat({spec}, 0, 0, 32, 32, c);
    EXPECT_NEAR(b.mean, a.mean, 5 * std::sqrt(a.se * a.se + b.se * b.se) + 3e-3 * a.mean) << "channel " << c;
  }
  EXPECT_EQ(blocks, 48);
}

// 3. The hero-wavelength estimator is unbiased: the mean of many 1-spp spectral renders
// of a diffuse plane ρ(λ) under a uniform environment E(λ) — every pixel sees L = ρ E
// (irradiance π E, f = ρ/π) — equals the XYZ of ρ E integrated over all wavelengths here.
void expect_plane_under_sky(const std::string& reflectance, const std::string& environment,
                            const std::function<double(double)>& radiance, const std::string& what) {
  const int renders = spp(16, 4);
  std::vector<Image> images;
  for (int seed = 0; seed < renders; ++seed)
    images.push_back(render_text(
        R"({"camera": {"position": [0, 3, 0], "look_at": [0, 0, 0], "up": [0, 0, -1], "fov": 40, "width": 48, "height": 48},
      "render": {"spp": 1, "spectral": true, "seed": )" +
        std::to_string(100 + seed) + R"(},
      "shapes": [{"type": "quad", "corner": [-5, 0, -5], "edge1": [0, 0, 10], "edge2": [10, 0, 0],
                  "material": {"type": "diffuse", "reflectance": )" +
        reflectance + R"(}}], "environment": {"radiance": )" + environment + "}}"));
  const auto expected = srgb_of_radiance(radiance);
  for (int c = 0; c < 3; ++c) {
    const Stat s = block_stat(images, 0, 0, 48, 48, c);
    EXPECT_NEAR(s.mean, expected[size_t(c)], 5 * s.se + 2e-3 * std::abs(expected[size_t(c)]))
        << what << ", channel " << c << " (se " << s.se << ")";
    EXPECT_LT(s.se, 0.05 * std::max(0.2, std::abs(expected[size_t(c)]))) << what;
  }
}

TEST(SpectralRender, HeroWavelengthsUnbiasedForSpectrumInputs) {
  // Piecewise-linear spectra written here, evaluated here.
  auto rho = [](double l) {
    if (l <= 500) return 0.1 + 0.8 * (l - 360) / 140;
    if (l <= 600) return 0.9 - 0.7 * (l - 500) / 100;
    return 0.2 + 0.4 * (l - 600) / 230;
  };
  auto sky = [](double l) { return l <= 550 ? 0.5 + 1.5 * (l - 360) / 190 : 2.0 - 1.0 * (l - 550) / 280; };
  expect_plane_under_sky(R"({"spectrum": [[360, 0.1], [500, 0.9], [600, 0.2], [830, 0.6]]})",
                         R"({"spectrum": [[360, 0.5], [550, 2], [830, 1]]})",
                         [&](double l) { return rho(l) * sky(l); }, "spectrum inputs");
}

TEST(SpectralRender, HeroWavelengthsUnbiasedForRgbInputs) {
  // The RGB inputs' spectra are gonio's upsampling (the inputs of the estimator under
  // test, not its output): ρ = RgbAlbedoSpectrum, E = RgbIlluminantSpectrum (m S(rgb/m)
  // D65, m = 2 max).
  const RgbAlbedoSpectrum rho(0.7f, 0.4f, 0.1f);
  const RgbIlluminantSpectrum sky(0.2f, 0.5f, 1.5f);
  expect_plane_under_sky("[0.7, 0.4, 0.1]", "[0.2, 0.5, 1.5]",
                         [&](double l) { return double(rho.eval(Float(l))) * double(sky.eval(Float(l))); }, "RGB inputs");
}

// Lights given as spectra (a quad and a point light each emitting a 20 nm band, a point
// light of a 3000 K blackbody, a sphere of D65) over a diffuse plane ρ(λ): one bounce, so
// the image
// is G(x, y) ρ(λ) S(λ), with G the geometry alone. G is measured by rendering the same
// geometry in RGB mode with ρ = 1 and a light of 1 (no spectral code involved); each
// 8×8 block of the spectral image must be G times the sRGB of ρ S integrated here. The
// bands make the light's spectrum matter: reduced to RGB and upsampled again (a smooth
// metamer), the result would differ by tens of percent.
TEST(SpectralRender, SpectrumLightsOverAPlaneAreTheGeometryTimesTheirColour) {
  const std::string plane_rho = R"({"spectrum": [[360, 0.1], [500, 0.9], [600, 0.2], [830, 0.6]]})";
  auto rho = [](double l) {
    if (l <= 500) return 0.1 + 0.8 * (l - 360) / 140;
    if (l <= 600) return 0.9 - 0.7 * (l - 500) / 100;
    return 0.2 + 0.4 * (l - 600) / 230;
  };
  // Planck's law (SI 2019 constants), normalised here to luminance Y = 1 as SPEC §2's
  // {"blackbody": K} is.
  auto planck = [](double l_nm) {
    const double h = 6.62607015e-34, c = 299792458, k = 1.380649e-23, l = l_nm * 1e-9, T = 3000;
    return 2 * h * c * c / std::pow(l, 5) / std::expm1(h * c / (l * k * T));
  };
  const double planck_y = xyz_of_radiance(planck)[1];
  const auto d65 = read_data("cie/cie_illuminant_d65.csv");
  const double d65_y = xyz_of_radiance([&](double l) { return lerp_rows(d65, l); })[1];
  struct Case {
    std::string name, light_spectral, light_grey;
    std::function<double(double)> emission;
  };
  const std::vector<Case> cases = {
      {"quad", R"({"type": "quad", "corner": [1.2, 1, -0.5], "edge1": [1, 0, 0], "edge2": [0, 0, 1], "radiance": {"spectrum": [[360, 0], [590, 0], [600, 40], [610, 0], [830, 0]]}})",
       R"({"type": "quad", "corner": [1.2, 1, -0.5], "edge1": [1, 0, 0], "edge2": [0, 0, 1], "radiance": 1})",
       [](double l) { return std::max(0.0, 40 - 4 * std::abs(l - 600)); }},
      {"point band", R"({"type": "point", "position": [0.3, 1.5, -0.2], "intensity": {"spectrum": [[360, 0], [450, 0], [460, 10], [470, 0], [830, 0]]}})",
       R"({"type": "point", "position": [0.3, 1.5, -0.2], "intensity": 1})",
       [](double l) { return std::max(0.0, 10 - std::abs(l - 460)); }},
      {"point", R"({"type": "point", "position": [0.3, 1.5, -0.2], "intensity": {"blackbody": 3000}})",
       R"({"type": "point", "position": [0.3, 1.5, -0.2], "intensity": 1})",
       [&](double l) { return planck(l) / planck_y; }},
      {"sphere", R"({"type": "sphere", "center": [-1.5, 1.2, 0.5], "radius": 0.3, "radiance": {"illuminant": "D65"}})",
       R"({"type": "sphere", "center": [-1.5, 1.2, 0.5], "radius": 0.3, "radiance": 1})",
       [&](double l) { return lerp_rows(d65, l) / d65_y; }},
  };
  auto scene = [&](const std::string& rho_json, const std::string& light, bool spectral, int seed) {
    return std::string(R"({"camera": {"position": [0, 3, 0], "look_at": [0, 0, 0], "up": [0, 0, -1], "fov": 40, "width": 32, "height": 32},
      "render": {"spp": )") + std::to_string(spp(64, 16)) + R"(, "seed": )" + std::to_string(seed) + R"(, "spectral": )" +
           (spectral ? "true" : "false") + R"(},
      "shapes": [{"type": "quad", "corner": [-5, 0, -5], "edge1": [0, 0, 10], "edge2": [10, 0, 0], "material": {"type": "diffuse", "reflectance": )" +
           rho_json + R"(}}], "lights": [)" + light + "]}";
  };
  for (const Case& k : cases) {
    const Image g = render_text(scene("1", k.light_grey, false, 5));
    const Image s = render_text(scene(plane_rho, k.light_spectral, true, 6));
    const auto colour = srgb_of_radiance([&](double l) { return rho(l) * k.emission(l); });
    for (int by = 0; by < 32; by += 8) {
      for (int bx = 0; bx < 32; bx += 8) {
        const Stat geo = block_stat({g}, bx, by, 8, 8, 0);
        for (int c = 0; c < 3; ++c) {
          const Stat b = block_stat({s}, bx, by, 8, 8, c);
          const double e = colour[size_t(c)];
          const double expected = geo.mean * e;
          const double sigma = std::sqrt(b.se * b.se + e * e * geo.se * geo.se);
          EXPECT_NEAR(b.mean, expected, 5 * sigma + 3e-3 * std::abs(expected))
              << k.name << " light, block " << bx << "," << by << " channel " << c;
        }
      }
    }
  }
}

// Textured colours in spectral mode are upsampled from the texel's RGB: a checker of two
// colours too fine for a pixel renders, under a white environment, to the mean of the
// two colours, as in RGB mode.
TEST(SpectralRender, TexturedColoursRenderAsInRgbMode) {
  auto scene = [](bool spectral, int seed) {
    return std::string(R"({"camera": {"position": [0, 3, 0], "look_at": [0, 0, 0], "up": [0, 0, -1], "fov": 40, "width": 32, "height": 32},
      "render": {"spp": )") + std::to_string(spp(32, 8)) + R"(, "seed": )" + std::to_string(seed) + R"(, "spectral": )" +
           (spectral ? "true" : "false") + R"(},
      "shapes": [{"type": "quad", "corner": [-5, 0, -5], "edge1": [0, 0, 10], "edge2": [10, 0, 0],
                  "material": {"type": "diffuse", "reflectance": {"checker": [[0.8, 0.3, 0.1], [0.1, 0.5, 0.9]], "uv_scale": [2000, 2000]}}}],
      "environment": {"radiance": 1}})";
  };
  const Image rgb = render_text(scene(false, 7));
  const Image spec = render_text(scene(true, 8));
  const double expected[3] = {0.45, 0.4, 0.5};
  for (int c = 0; c < 3; ++c) {
    const Stat a = block_stat({rgb}, 0, 0, 32, 32, c), b = block_stat({spec}, 0, 0, 32, 32, c);
    EXPECT_NEAR(a.mean, expected[c], 0.01) << "RGB mode, channel " << c;
    EXPECT_NEAR(b.mean, a.mean, 5 * std::sqrt(a.se * a.se + b.se * b.se) + 3e-3) << "channel " << c;
  }
}

}  // namespace
}  // namespace gonio::render::test
