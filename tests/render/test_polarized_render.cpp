// Polarized rendering (issue 15, items 4 and 5) against expectations made here, not by
// the code under test: the polarization of light reflected off glass from this file's own
// Fresnel equations and the geometry of the camera (its roll turns the angle of
// polarization the other way); a mirror before the glass turns the polarization plane as
// the reflection of a vector does; Malus's law between a render through a polarizer and
// the unfiltered Stokes images; and S0 equal to the unpolarized render where a path has
// one bounce (where polarization cannot change intensity).

#include <array>
#include <cmath>
#include <numbers>
#include <string>

#include <gtest/gtest.h>

#include "../test_common.h"
#include "gonio/render/colormap.h"
#include "gonio/render/stokes_image.h"
#include "render_test_util.h"

namespace gonio::render::test {
namespace {


StokesImages render_stokes(const std::string& json, int threads = 0) {
  const Scene scene = parse_scene(json, "test scene", "");
  RenderOptions options;
  options.threads = threads;
  StokesImages s;
  render(scene, options, nullptr, &s);
  return s;
}

// Mean over the whole image of one component's luminance-weighted channel sum (the test
// scenes are grey, so any channel would do; the luminance checks all three).
double mean_luminance(const Image& img) {
  double s = 0;
  for (int y = 0; y < img.height(); ++y)
    for (int x = 0; x < img.width(); ++x) s += luminance(img.at(x, y));
  return s / (double(img.width()) * img.height());
}

// Fresnel reflectances of a dielectric interface for light from the side of index 1
// (Born & Wolf §1.5.2, eqs. 35): r_s = (cos i − n cos t)/(cos i + n cos t),
// r_p = (n cos i − cos t)/(n cos i + cos t).
void fresnel_rs_rp(double cos_i, double n, double& Rs, double& Rp) {
  const double sin_t = std::sqrt(1 - cos_i * cos_i) / n, cos_t = std::sqrt(1 - sin_t * sin_t);
  const double rs = (cos_i - n * cos_t) / (cos_i + n * cos_t), rp = (n * cos_i - cos_t) / (n * cos_i + cos_t);
  Rs = rs * rs;
  Rp = rp * rp;
}

std::string vec(double x, double y, double z) {
  char buf[128];
  std::snprintf(buf, sizeof buf, "[%.9g, %.9g, %.9g]", x, y, z);
  return buf;
}

// A smooth glass floor (η = 1.5) with a black layer under it, under a uniform sky of
// radiance 1, seen at `theta` from its normal through a 1° field of view, the camera
// rolled by `roll` (counter-clockwise as its viewer sees it).
std::string glass_floor_scene(double theta, double roll, int spp, const std::string& extra_render = "") {
  const double c = std::cos(theta), s = std::sin(theta);
  // Unrolled: right = +x, up = (0, s, −c)·sign so that it is ⊥ the view (0, −c, −s).
  const double ux = -std::sin(roll), uy = std::cos(roll) * s, uz = -std::cos(roll) * c;
  return R"({"camera": {"position": )" + vec(0, 2 * c, 2 * s) + R"(, "look_at": [0, 0, 0], "up": )" + vec(ux, uy, uz) +
         R"(, "fov": 1, "width": 8, "height": 8},
    "render": {"spp": )" + std::to_string(spp) + R"(, "max_depth": 4, "rr_depth": 64, "polarized": true)" + extra_render + R"(},
    "shapes": [
      {"type": "quad", "corner": [-50, 0, -50], "edge1": [0, 0, 100], "edge2": [100, 0, 0], "material": {"type": "dielectric", "eta": 1.5}},
      {"type": "quad", "corner": [-50, -0.01, -50], "edge1": [0, 0, 100], "edge2": [100, 0, 0], "material": {"type": "diffuse", "reflectance": 0}}
    ],
    "environment": {"radiance": 1}})";
}

struct Polarization {
  double s0, q, u, v;  // S1/S0, S2/S0, S3/S0 as q, u, v
};

Polarization mean_polarization(const StokesImages& img) {
  const double s0 = mean_luminance(img[0]);
  return {s0, mean_luminance(img[1]) / s0, mean_luminance(img[2]) / s0, mean_luminance(img[3]) / s0};
}

// Light reflected off glass is partially polarized along s, ⊥ the plane of incidence:
// DoLP = (Rs − Rp)/(Rs + Rp), Q/I = DoLP cos 2χ and U/I = DoLP sin 2χ, with χ the angle of
// s in the image. Here s is the world's x axis, the unrolled image's x axis; rolling the
// camera counter-clockwise by ψ turns it to χ = −ψ in the image.
TEST(PolarizedRender, GlassReflectionHasTheFresnelPolarizationInTheImageFrame) {
  for (const double theta_deg : {56.309932474020215, 70.0, 30.0})
    for (const double roll_deg : {0.0, 30.0, -55.0, 100.0}) {
      SCOPED_TRACE("theta " + std::to_string(theta_deg) + "°, roll " + std::to_string(roll_deg) + "°");
      const StokesImages img = render_stokes(glass_floor_scene(theta_deg * kDeg, roll_deg * kDeg, 64));
      double Rs, Rp;
      fresnel_rs_rp(std::cos(theta_deg * kDeg), 1.5, Rs, Rp);
      const double dolp = (Rs - Rp) / (Rs + Rp), chi = -roll_deg * kDeg;
      const Polarization p = mean_polarization(img);
      // Every reflected path has the same polarization (to the 1° field of view), so
      // the ratios carry no noise; the intensity has that of choosing reflection with
      // probability R per sample: relative σ = √((1 − R)/(R N)), N = 4096.
      EXPECT_NEAR(p.q, dolp * std::cos(2 * chi), 0.01);
      EXPECT_NEAR(p.u, dolp * std::sin(2 * chi), 0.01);
      EXPECT_NEAR(p.v, 0, 1e-6);  // a dielectric reflection below the critical angle has no retardance
      const double R = (Rs + Rp) / 2, sigma = R * std::sqrt((1 - R) / (R * 4096));
      EXPECT_NEAR(p.s0, R, 4 * sigma + 0.002 * R);
      // The angle and degree of the mean Stokes vector (a pixel alone may have no
      // reflected sample at 30°, where R = 4%).
      StokesImages mean{Image(1, 1), Image(1, 1), Image(1, 1), Image(1, 1)};
      for (size_t k = 0; k < 4; ++k) mean[k].at(0, 0) = img[k].average();
      const LinearPolarization lp = linear_polarization(mean, 0, 0);
      EXPECT_NEAR(lp.dolp, dolp, 0.01);
      if (dolp > 0.1) {
        double want = std::fmod(-roll_deg + 360, 180.0);
        double diff = std::remainder(lp.aolp_deg - want, 180.0);
        EXPECT_NEAR(diff, 0, 1.0);
      }
    }
}

// The same in spectral mode: the glass's η = 1.5 at every wavelength, so the polarization
// is the same at each, and the film's XYZ → sRGB keeps a grey Stokes vector grey.
TEST(PolarizedRender, SpectralGlassReflectionHasTheFresnelPolarization) {
  const double theta = 65 * kDeg, roll = 20 * kDeg;
  const StokesImages img = render_stokes(glass_floor_scene(theta, roll, 64, R"(, "spectral": true)"));
  double Rs, Rp;
  fresnel_rs_rp(std::cos(theta), 1.5, Rs, Rp);
  const double dolp = (Rs - Rp) / (Rs + Rp);
  const Polarization p = mean_polarization(img);
  EXPECT_NEAR(p.q, dolp * std::cos(-2 * roll), 0.01);
  EXPECT_NEAR(p.u, dolp * std::sin(-2 * roll), 0.01);
}

// Next-event estimation carries polarization too: a rough glass floor (GGX, α = 0.3,
// black beneath) lit by a point light, nothing else, one bounce, the light off to the side
// of the camera's mirror direction. What reaches the film is the Fresnel reflection of the
// microfacet that joins the two directions, h = (wo + wi)/|wo + wi|: polarized with degree
// P(wo·h) = (Rs − Rp)/(Rs + Rp) along the facet's s = wi × wo, whose angle χ in the image
// axes (x, y) gives S1/S0 = P cos 2χ, S2/S0 = P sin 2χ. The facet's plane of incidence is
// not the floor's, so the frames of wo and wi both turn.
TEST(PolarizedRender, PointLightOffRoughGlassHasTheFacetsFresnelPolarization) {
  using V = std::array<double, 3>;
  auto dot3 = [](const V& a, const V& b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; };
  auto cross3 = [](const V& a, const V& b) {
    return V{a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]};
  };
  auto unit = [&](const V& a) {
    const double l = std::sqrt(dot3(a, a));
    return V{a[0] / l, a[1] / l, a[2] / l};
  };
  const double theta = 60 * kDeg, roll = 25 * kDeg, c = std::cos(theta), s = std::sin(theta);
  for (const double side : {0.0, 0.8, -1.5}) {
    SCOPED_TRACE("light moved sideways by " + std::to_string(side));
    const V cam = {0, 2 * c, 2 * s}, light = {side, 2 * c, -2 * s};
    const V up = {-std::sin(roll), std::cos(roll) * s, -std::cos(roll) * c};
    const std::string scene = R"({"camera": {"position": )" + vec(cam[0], cam[1], cam[2]) +
                              R"(, "look_at": [0, 0, 0], "up": )" + vec(up[0], up[1], up[2]) +
                              R"(, "fov": 1, "width": 8, "height": 8},
      "render": {"spp": 4, "max_depth": 1, "polarized": true},
      "shapes": [
        {"type": "quad", "corner": [-50, 0, -50], "edge1": [0, 0, 100], "edge2": [100, 0, 0], "material": {"type": "roughdielectric", "eta": 1.5, "alpha": 0.3}},
        {"type": "quad", "corner": [-50, -0.01, -50], "edge1": [0, 0, 100], "edge2": [100, 0, 0], "material": {"type": "diffuse", "reflectance": 0}}
      ],
      "lights": [{"type": "point", "position": )" + vec(light[0], light[1], light[2]) + R"(, "intensity": 1}]})";
    const StokesImages img = render_stokes(scene);
    const V wo = unit(cam), wi = unit(light), h = unit({wo[0] + wi[0], wo[1] + wi[1], wo[2] + wi[2]});
    double Rs, Rp;
    fresnel_rs_rp(dot3(wo, h), 1.5, Rs, Rp);
    const double dolp = (Rs - Rp) / (Rs + Rp);
    // The image axes: x = forward × up (normalised), y = x × forward.
    const V forward = unit({-cam[0], -cam[1], -cam[2]});
    const V x = unit(cross3(forward, up)), y = cross3(x, forward);
    const V sf = unit(cross3(wi, wo));
    const double chi = std::atan2(dot3(sf, y), dot3(sf, x));
    const Polarization p = mean_polarization(img);
    EXPECT_GT(p.s0, 0);
    EXPECT_NEAR(p.q, dolp * std::cos(2 * chi), 0.01);
    EXPECT_NEAR(p.u, dolp * std::sin(2 * chi), 0.01);
  }
}

// A perfect mirror before the glass: the camera looks along −z at a mirror whose normal
// is (0, 1, 1)/√2, which sends the ray up (+y) to a glass plate tilted by θ = 60° from
// the ray, its plane of incidence turned by β = 30° about the ray. The glass polarizes the
// light along its s axis e = d × n_g; an ideal mirror reflects the field vector,
// e' = e − 2 (e·n_m) n_m, so the image's angle of polarization is that of e' in the image
// axes (x, y), and the degree is the glass's. This checks the frame carried from the
// glass to the mirror and from the mirror to the film.
TEST(PolarizedRender, MirrorThenGlassTurnsThePolarizationAsTheGeometrySays) {
  const double theta = 60 * kDeg, beta = 30 * kDeg;
  const std::array<double, 3> ng = {std::sin(theta) * std::cos(beta), -std::cos(theta), std::sin(theta) * std::sin(beta)};
  // Two edges of the glass ⊥ ng with edge1 × edge2 = ng (the side the light comes from).
  const std::array<double, 3> a = {0, 0, 1};
  auto cross = [](const std::array<double, 3>& u, const std::array<double, 3>& w) {
    return std::array<double, 3>{u[1] * w[2] - u[2] * w[1], u[2] * w[0] - u[0] * w[2], u[0] * w[1] - u[1] * w[0]};
  };
  auto norm = [](std::array<double, 3> u) {
    const double l = std::sqrt(u[0] * u[0] + u[1] * u[1] + u[2] * u[2]);
    return std::array<double, 3>{u[0] / l, u[1] / l, u[2] / l};
  };
  const auto e1 = norm(cross(a, ng)), e2 = cross(ng, e1);  // e1 × e2 = ng
  const double size = 0.5;
  auto quad = [&](double off, const std::string& material) {
    // Centred at (0, 1, 0) moved by `off` along −ng (the glass's far side).
    const double cx = -off * ng[0] - size / 2 * (e1[0] + e2[0]), cy = 1 - off * ng[1] - size / 2 * (e1[1] + e2[1]),
                 cz = -off * ng[2] - size / 2 * (e1[2] + e2[2]);
    return R"({"type": "quad", "corner": )" + vec(cx, cy, cz) + R"(, "edge1": )" +
           vec(size * e1[0], size * e1[1], size * e1[2]) + R"(, "edge2": )" + vec(size * e2[0], size * e2[1], size * e2[2]) +
           R"(, "material": )" + material + "}";
  };
  const std::string scene = R"({"camera": {"position": [0, 0, 2], "look_at": [0, 0, 0], "up": [0, 1, 0], "fov": 1, "width": 8, "height": 8},
    "render": {"spp": 32, "max_depth": 4, "rr_depth": 64, "polarized": true},
    "shapes": [
      {"type": "quad", "corner": [-0.25, -0.176776695, 0.176776695], "edge1": [0.5, 0, 0], "edge2": [0, 0.353553391, -0.353553391],
       "material": {"type": "conductor", "fresnel": "schlick", "f0": 1}},
      )" + quad(0, R"({"type": "dielectric", "eta": 1.5})") + ",\n" +
                            quad(0.01, R"({"type": "diffuse", "reflectance": 0})") + R"(
    ],
    "environment": {"radiance": 1}})";
  const StokesImages img = render_stokes(scene);

  const std::array<double, 3> d = {0, 1, 0}, nm = {0, 1 / std::sqrt(2.0), 1 / std::sqrt(2.0)};
  const auto e = norm(cross(d, ng));
  const double en = e[0] * nm[0] + e[1] * nm[1] + e[2] * nm[2];
  const std::array<double, 3> ep = {e[0] - 2 * en * nm[0], e[1] - 2 * en * nm[1], e[2] - 2 * en * nm[2]};
  const double chi = std::atan2(ep[1], ep[0]);  // image x = world +x, image y = world +y
  double Rs, Rp;
  fresnel_rs_rp(std::cos(theta), 1.5, Rs, Rp);
  const double dolp = (Rs - Rp) / (Rs + Rp);
  const Polarization p = mean_polarization(img);
  EXPECT_NEAR(p.q, dolp * std::cos(2 * chi), 0.01);
  EXPECT_NEAR(p.u, dolp * std::sin(2 * chi), 0.01);
  // The expectation is not a trivial one: the angle is neither 0° nor 90°.
  EXPECT_GT(std::abs(std::sin(2 * chi)), 0.3);
}

// A scene where paths bounce several times off polarizing and depolarizing surfaces.
std::string busy_scene(const std::string& camera_extra, const std::string& render_extra, int max_depth = 6) {
  return R"({"camera": {"position": [0, 1.4, 5], "look_at": [0, 0.5, 0], "fov": 40, "width": 24, "height": 24)" +
         camera_extra + R"(},
    "render": {"spp": 4, "max_depth": )" + std::to_string(max_depth) + R"(, "rr_depth": 64, "polarized": true, "seed": 7)" +
         render_extra + R"(},
    "shapes": [
      {"type": "quad", "corner": [-10, 0, -10], "edge1": [0, 0, 20], "edge2": [20, 0, 0], "material": {"type": "plastic", "reflectance": 0.4, "eta": 1.5}},
      {"type": "sphere", "center": [-1.2, 0.5, 0], "radius": 0.5, "material": {"type": "roughconductor", "material": "Au", "alpha": 0.2}},
      {"type": "sphere", "center": [0, 0.5, 0], "radius": 0.5, "material": {"type": "dielectric", "eta": 1.5}},
      {"type": "sphere", "center": [1.2, 0.5, 0], "radius": 0.5, "material": {"type": "conductor", "material": "Cu"}}
    ],
    "lights": [{"type": "quad", "corner": [-1, 3, -1], "edge1": [2, 0, 0], "edge2": [0, 0, 2], "radiance": 8},
               {"type": "point", "position": [2, 2, 2], "intensity": 5}],
    "environment": {"radiance": 0.3}})";
}

// Malus's law for a linear polarizer at φ before the film: I_φ = (S0 + S1 cos 2φ +
// S2 sin 2φ)/2 of the unfiltered Stokes images. Without Russian roulette the polarizer does
// not change which paths are sampled, so the two sides agree to rounding, not only within
// noise.
void expect_malus(const std::string& render_extra) {
  const StokesImages open = render_stokes(busy_scene("", render_extra));
  double polarized_pixels = 0;
  for (int y = 0; y < 24; ++y)
    for (int x = 0; x < 24; ++x)
      if (linear_polarization(open, x, y).dolp > 0.05) ++polarized_pixels;
  EXPECT_GT(polarized_pixels, 24 * 24 / 10) << "the scene must polarize for the test to mean anything";
  for (const double phi_deg : {0.0, 37.0, 90.0, 135.0}) {
    SCOPED_TRACE("polarizer at " + std::to_string(phi_deg) + "°");
    const double phi = phi_deg * kDeg;
    const StokesImages through =
        render_stokes(busy_scene(R"(, "polarizer": )" + std::to_string(phi_deg), render_extra));
    double worst = 0;
    for (int y = 0; y < 24; ++y)
      for (int x = 0; x < 24; ++x)
        for (int c = 0; c < 3; ++c) {
          const double want = (open[0].at(x, y)[c] + open[1].at(x, y)[c] * std::cos(2 * phi) +
                               open[2].at(x, y)[c] * std::sin(2 * phi)) / 2;
          const double got = through[0].at(x, y)[c];
          worst = std::max(worst, std::abs(got - want) / (1e-3 + std::abs(open[0].at(x, y)[c])));
        }
    EXPECT_LT(worst, 1e-4);
  }
}

TEST(PolarizedRender, MalusLawThroughTheCameraPolarizer) { expect_malus(""); }
TEST(PolarizedRender, MalusLawThroughTheCameraPolarizerSpectral) { expect_malus(R"(, "spectral": true)"); }

// One bounce (max_depth 1: the camera ray's vertex, lit by next-event estimation and by
// its BSDF sample's emitter): the film sees M00 of one Mueller matrix applied to
// unpolarized light, which is the unpolarized BSDF. S0 equals the unpolarized render, the
// same paths with the same random numbers.
TEST(PolarizedRender, OneBounceS0IsTheUnpolarizedRender) {
  for (const char* extra : {"", R"(, "spectral": true)"}) {
    SCOPED_TRACE(extra);
    const std::string polarized = busy_scene("", extra, 1);
    // The same scene without polarization.
    std::string plain = polarized;
    const std::string key = R"("polarized": true)";
    plain.replace(plain.find(key), key.size(), R"("polarized": false)");
    const StokesImages s = render_stokes(polarized);
    const Image unpolarized = render_text(plain);
    double worst = 0, total = 0;
    for (int y = 0; y < 24; ++y)
      for (int x = 0; x < 24; ++x)
        for (int c = 0; c < 3; ++c) {
          const double a = s[0].at(x, y)[c], b = unpolarized.at(x, y)[c];
          worst = std::max(worst, std::abs(a - b) / (1e-6 + std::abs(b)));
          total += b;
        }
    EXPECT_GT(total, 0);
    EXPECT_LT(worst, 1e-5);
    // And the scene polarizes at one bounce, so the S0 equality is not that of a
    // depolarizing scene.
    double polarized_pixels = 0;
    for (int y = 0; y < 24; ++y)
      for (int x = 0; x < 24; ++x)
        if (linear_polarization(s, x, y).dolp > 0.05) ++polarized_pixels;
    EXPECT_GT(polarized_pixels, 10);
  }
}

// Unpolarized light through a polarizer and nothing else polarizing: the camera sees
// half the intensity, fully polarized along the polarizer's axis.
TEST(PolarizedRender, PolarizerAloneHalvesADepolarizedImage) {
  const std::string scene = R"({"camera": {"position": [0, 1, 3], "look_at": [0, 0, 0], "fov": 30, "width": 8, "height": 8, "polarizer": 30},
    "render": {"spp": 16, "polarized": true},
    "shapes": [{"type": "quad", "corner": [-10, 0, -10], "edge1": [0, 0, 20], "edge2": [20, 0, 0], "material": {"type": "diffuse", "reflectance": 0.5}}],
    "environment": {"radiance": 1}})";
  const StokesImages s = render_stokes(scene);
  for (int y = 0; y < 8; ++y)
    for (int x = 0; x < 8; ++x) {
      // A diffuse floor under a uniform sky of radiance 1 has radiance ρ = 0.5 (with the
      // noise of its hemisphere sampling); behind the polarizer half of it, all along 30°.
      // The raw ratios first (linear_polarization clamps the degree to 1): a polarizer
      // at 30° passes S ∝ (1, cos 60°, sin 60°, 0).
      const double s0 = luminance(s[0].at(x, y));
      EXPECT_NEAR(luminance(s[1].at(x, y)) / s0, 0.5, 1e-4);
      EXPECT_NEAR(luminance(s[2].at(x, y)) / s0, std::sqrt(3.0) / 2, 1e-4);
      EXPECT_NEAR(luminance(s[3].at(x, y)) / s0, 0, 1e-6);
      const LinearPolarization lp = linear_polarization(s, x, y);
      EXPECT_NEAR(lp.dolp, 1, 1e-4);
      EXPECT_NEAR(lp.aolp_deg, 30, 0.01);
    }
  EXPECT_NEAR(mean_luminance(s[0]), 0.25, 0.01);
}

}  // namespace
}  // namespace gonio::render::test
