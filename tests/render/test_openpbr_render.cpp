// `openpbr` in `gonio render` beyond its BSDF (issue 35, stage 2; docs/openpbr.md,
// "Rendering"): emission (emission_luminance × emission_color, under the coat) and the
// interior medium of a transmitting shape (transmission_color at transmission_depth, SPEC-OPB
// "Translucent base"), each against a closed form.

#include <cmath>
#include <string>

#include <gtest/gtest.h>

#include "gonio/render/scene_loader.h"
#include "gonio/subsurface/openpbr_interior.h"
#include "render_test_util.h"
#include "scratch_dir.h"

namespace gonio::render::test {
namespace {

// Looking straight down from height y at the origin, with a vertical field of view of fov°.
std::string opb_camera(int size, double y, double fov) {
  return R"("camera": {"position": [0, )" + std::to_string(y) + R"(, 0], "look_at": [0, 0, 0], "up": [0, 0, -1], "fov": )" +
         std::to_string(fov) + R"(, "width": )" + std::to_string(size) +
         R"(, "height": )" + std::to_string(size) + "}";
}

// An emitting sphere lights a Lambertian plane as the sphere light of
// Render.SphereLightOverDiffusePlaneMatchesClosedForm does: L_out = ρ L r²/d² (Howell, factor
// B-5). The sphere reflects nothing (base_weight 0, specular_weight 0), so only its emission
// counts; next-event estimation samples it and BSDF samples that hit it are weighted against
// that (a wrong MIS weight or a missing light registration biases the estimate).
TEST(OpenPbrRender, EmittingSphereLightsAPlaneAsASphereLight) {
  const double rho = 0.5, L = 5, r = 0.4, d = 1.2;
  const Image img = render_text(R"({"camera": {"position": [0, 0.6, 0], "look_at": [0, 0, 0], "up": [0, 0, -1], "fov": 40,
      "width": 16, "height": 16}, "render": {"spp": 512},
    "shapes": [{"type": "quad", "corner": [-5, 0, -5], "edge1": [0, 0, 10], "edge2": [10, 0, 0], "material": {"type": "diffuse", "reflectance": 0.5}},
               {"type": "sphere", "center": [0, 1.2, 0], "radius": 0.4, "material": {"type": "openpbr", "base_weight": 0,
                "specular_weight": 0, "emission_luminance": 5, "emission_color": 1}}]})");
  const double expected = rho * L * r * r / (d * d);
  for (int c = 0; c < 3; ++c) EXPECT_NEAR(block_mean(img, 7, 7, 2, c), expected, 0.02 * expected) << "channel " << c;
}

// An emitting rectangle (facing down) over a Lambertian plane: L_out = ρ L F, F the form
// factor from a point under the centre of a 2a × 2b rectangle at height h to it (Howell,
// C-11; render_test_util.h). As a quad shape it is a light that next-event estimation
// samples; as the same quad in an OBJ mesh it is not (meshes emit where paths hit them), and
// only BSDF samples find it: both must give the same image.
TEST(OpenPbrRender, EmittingQuadAndMeshLightAPlaneByTheFormFactor) {
  const double a = 0.6, b = 0.9, h = 1.0, L = 3, rho = 0.5;
  const double F = centred_rectangle_form_factor(a, b, h);
  const std::string emitter =
      R"({"type": "openpbr", "base_weight": 0, "specular_weight": 0, "emission_luminance": 3, "emission_color": 1})";
  const gonio::test::ScratchDir dir("gonio_opb_render");
  dir.file("panel.obj", "v -0.6 1 -0.9\nv 0.6 1 -0.9\nv 0.6 1 0.9\nv -0.6 1 0.9\nf 1 3 4\nf 1 2 3\n");
  for (const std::string& shape :
       {R"({"type": "quad", "corner": [-0.6, 1, -0.9], "edge1": [1.2, 0, 0], "edge2": [0, 0, 1.8], "material": )" + emitter + "}",
        R"({"type": "mesh", "file": ")" + dir.path("panel.obj") + R"(", "material": )" + emitter + "}"}) {
    const Image img = render_text(R"({"camera": {"position": [0, 0.5, 0], "look_at": [0, 0, 0], "up": [0, 0, -1], "fov": 4,
        "width": 2, "height": 2}, "render": {"spp": 4096},
      "shapes": [{"type": "quad", "corner": [-5, 0, -5], "edge1": [0, 0, 10], "edge2": [10, 0, 0], "material": {"type": "diffuse", "reflectance": 0.5}},
                 )" + shape + "]}");
    EXPECT_NEAR(block_mean(img, 0, 0, 2, 1), rho * L * F, 0.02 * rho * L * F) << shape;
  }
}

// The emission lies under the coat (SPEC-OPB "Emission"): seen along the normal through a
// smooth coat of index n and colour κ, L_out = L [1 − C + C sqrt(κ) (1 − F0)], F0 =
// ((n − 1)/(n + 1))², sqrt(κ) the coat's one-way transmittance at normal incidence. The
// camera looks down the sphere's normal at its top; nothing else is lit.
TEST(OpenPbrRender, EmissionLeavesThroughTheCoat) {
  const double L = 3, n = 1.6, kappa = 0.25;
  const double f0 = (n - 1) * (n - 1) / ((n + 1) * (n + 1));
  for (const double C : {1.0, 0.5}) {
    const Image img = render_text(R"({)" + opb_camera(8, 5, 2) + R"(, "render": {"spp": 4},
      "shapes": [{"type": "sphere", "center": [0, 0, 0], "radius": 2, "material": {"type": "openpbr", "base_weight": 0,
        "specular_weight": 0, "emission_luminance": 3, "coat_weight": )" + std::to_string(C) +
                                  R"(, "coat_roughness": 0, "coat_ior": 1.6, "coat_color": 0.25}}]})");
    const double expected = L * (1 - C + C * std::sqrt(kappa) * (1 - f0));
    // The central pixels see the top within 0.4° (of the sphere's normal), where μ > 0.9999.
    EXPECT_NEAR(block_mean(img, 3, 3, 2, 0), expected, 2e-3 * expected) << "coat_weight " << C;
  }
}

// An index-matched (specular_ior 1), smooth, transmitting sphere neither reflects nor bends
// light: a ray through its centre crosses 2r of its interior, so against a uniform
// environment L_e the pixel is L_e · transmission_color^(2r/d) (Beer–Lambert with SPEC-OPB's
// μt = −ln(C)/d), per channel — in RGB, spectral (a grey colour upsamples to a flat
// spectrum) and polarized mode alike.
TEST(OpenPbrRender, InteriorAbsorbsAsBeerLambert) {
  const double r = 1, d = 0.8, Le = 2;
  const double colour[3] = {0.7, 0.4, 0.9};
  for (const char* mode : {"", R"(, "spectral": true)", R"(, "polarized": true)"}) {
    const bool grey = *mode != 0;
    const std::string c = grey ? "0.4" : "[0.7, 0.4, 0.9]";
    const Image img = render_text(R"({)" + opb_camera(2, 6, 0.125) + R"(, "render": {"spp": )" + (grey ? "1024" : "4") + mode + R"(},
      "shapes": [{"type": "sphere", "center": [0, 0, 0], "radius": 1, "material": {"type": "openpbr", "transmission_weight": 1,
        "specular_roughness": 0, "specular_ior": 1, "transmission_color": )" + c + R"(, "transmission_depth": 0.8}}],
      "environment": {"radiance": 2}})");
    for (int ch = 0; ch < 3; ++ch) {
      const double C = grey ? 0.4 : colour[ch];
      const double expected = Le * std::pow(C, 2 * r / d);
      // The 2 × 2 pixels' rays pass within 0.007 of the centre: chord ≥ 0.99997 · 2r.
      EXPECT_NEAR(block_mean(img, 0, 0, 2, ch), expected, 2e-3 * expected + 1e-4) << "mode '" << mode << "' channel " << ch;
    }
  }
}

// SPEC-OPB "Translucent base": μt = −ln(C)/d, μs = S/d, μa = μt − μs, raised in every
// channel by the most negative μa's magnitude when one is negative. Figures by hand.
TEST(OpenPbrRender, TransmissionMediumFollowsTheSpec) {
  OpenPbrParams<Color> p;
  p.transmission_weight = 1;
  p.transmission_depth = 2;
  p.transmission_color = Color(0.5f);
  p.transmission_scatter = Color(0.1f, 0.2f, 0.3f);
  auto m = openpbr::transmission_medium(p);
  ASSERT_TRUE(m);
  const double mu_t = std::log(2.0) / 2;  // 0.346574
  const double s[3] = {0.05, 0.1, 0.15};
  for (int c = 0; c < 3; ++c) {
    EXPECT_NEAR(m->sigma_s[c], s[c], 1e-6);
    EXPECT_NEAR(m->sigma_a[c], mu_t - s[c], 1e-6);
  }
  // μs = (0.5, 0.05, 0.05) exceeds μt = 0.0527 in red: μa = μt − μs = (−0.4473, 0.0027, 0.0027)
  // is raised by 0.4473 to (0, 0.45, 0.45).
  p.transmission_color = Color(0.9f);
  p.transmission_scatter = Color(1.0f, 0.1f, 0.1f);
  m = openpbr::transmission_medium(p);
  ASSERT_TRUE(m);
  EXPECT_NEAR(m->sigma_a[0], 0, 1e-6);
  EXPECT_NEAR(m->sigma_a[1], 0.5 - 0.05, 1e-5);
  EXPECT_NEAR(m->sigma_a[2], 0.5 - 0.05, 1e-5);
  EXPECT_NEAR(m->sigma_t()[1], 0.5, 1e-5);
  // No medium: thin-walled, no depth, no transmission.
  p.geometry_thin_walled = true;
  EXPECT_FALSE(openpbr::transmission_medium(p));
  p.geometry_thin_walled = false;
  p.transmission_depth = 0;
  EXPECT_FALSE(openpbr::transmission_medium(p));
}

// SPEC-OPB "Subsurface" in an RGB render: the subsurface share of the base becomes the
// specular interface over a medium of mean free path r = subsurface_radius ×
// subsurface_radius_scale (μt = 1/r) and albedo subsurface_color. White (colour 1: ϖ = 1,
// nothing absorbed) and in a white furnace, every path that is not cut short returns 1 —
// for S = 1, and for S = ½ over a white base, where the other half is the glossy-diffuse
// base (its own furnace holds, OpenPbrFurnace.*). A dropped or doubled share of either
// part, or a medium that absorbed, would move the image off 1.
TEST(OpenPbrRender, SubsurfaceVolumeFurnace) {
  for (const std::string& material :
       {std::string(R"({"type": "openpbr", "subsurface_weight": 1, "subsurface_color": 1, "subsurface_radius": 0.2,
           "subsurface_radius_scale": [1, 0.5, 0.25], "specular_roughness": 0})"),
        std::string(R"({"type": "openpbr", "subsurface_weight": 0.5, "subsurface_color": 1, "base_color": 1,
           "subsurface_radius": 0.3, "specular_roughness": 0})")}) {
    const Scene scene = parse_scene(R"({"camera": {"position": [0, 0, 6], "look_at": [0, 0, 0], "fov": 8, "width": 8,
        "height": 8}, "render": {"spp": 16, "max_depth": 1024},
      "shapes": [{"type": "sphere", "center": [0, 0, 0], "radius": 1, "material": )" + material + R"(}],
      "environment": {"radiance": 1}})", "furnace.json", "");
    ASSERT_TRUE(scene.materials[0].subsurface) << material;
    const Medium& m = scene.materials[0].subsurface->medium;
    EXPECT_TRUE(m.sigma_a.is_black()) << material;
    const Image img = render(scene, {});
    for (int c = 0; c < 3; ++c) {
      double sum = 0, sum2 = 0;
      for (int y = 0; y < 8; ++y)
        for (int x = 0; x < 8; ++x) {
          sum += img.at(x, y)[c];
          sum2 += double(img.at(x, y)[c]) * img.at(x, y)[c];
        }
      const double mean = sum / 64, err = std::sqrt(std::max(0.0, sum2 / 64 - mean * mean) / 63);
      EXPECT_NEAR(mean, 1.0, 4 * err + 1e-3) << material << " channel " << c << " ± " << err;
    }
  }
  // The share: over a black base (base_color 0), S = ½ of the base is the white volume under
  // the smooth interface, which returns all it receives in the furnace, and ½ the bare
  // interface, which reflects F: seen along the normal, ½ + ½ F0, F0 = 0.04 for η = 1.5.
  {
    const Image img = render_text(R"({"camera": {"position": [0, 0, 6], "look_at": [0, 0, 0], "fov": 1, "width": 2,
        "height": 2}, "render": {"spp": 8192, "max_depth": 1024},
      "shapes": [{"type": "sphere", "center": [0, 0, 0], "radius": 1, "material": {"type": "openpbr", "subsurface_weight": 0.5,
        "subsurface_color": 1, "base_color": 0, "subsurface_radius": 0.3, "specular_roughness": 0}}],
      "environment": {"radiance": 1}})");
    const double expected = 0.5 + 0.5 * 0.04;
    for (int c = 0; c < 3; ++c) EXPECT_NEAR(block_mean(img, 0, 0, 2, c), expected, 0.012) << "channel " << c;
  }
  // μt = 1/r per channel.
  const Scene scene = parse_scene(R"({"shapes": [{"type": "sphere", "center": [0, 0, 0], "radius": 1, "material":
      {"type": "openpbr", "subsurface_weight": 1, "subsurface_color": 0.6, "subsurface_radius": 0.2,
       "subsurface_radius_scale": [1, 0.5, 0.25]}}]})", "s.json", "");
  const Color sigma_t = scene.materials[0].subsurface->medium.sigma_t();
  EXPECT_NEAR(sigma_t[0], 5, 5e-5);
  EXPECT_NEAR(sigma_t[1], 10, 1e-4);
  EXPECT_NEAR(sigma_t[2], 20, 2e-4);
  EXPECT_FALSE(scene.materials[0].subsurface->medium.sigma_a.is_black());
}

// A textured emission (a checker of emission_luminance 0 and 4 on a quad seen head-on): the
// quad is not a sampled light then (its radiance varies), and paths that meet it read the
// texture: each quarter of the image shows its square's value, 0 or 4, in a checker.
TEST(OpenPbrRender, TexturedEmissionIsReadWherePathsMeetIt) {
  const Image img = render_text(R"({"camera": {"position": [0, 0, 5], "look_at": [0, 0, 0], "fov": 20, "width": 8,
      "height": 8}, "render": {"spp": 4},
    "shapes": [{"type": "quad", "corner": [-1, -1, 0], "edge1": [2, 0, 0], "edge2": [0, 2, 0], "material": {"type": "openpbr",
      "base_weight": 0, "specular_weight": 0, "emission_luminance": {"checker": [0, 4], "uv_scale": 2}}}]})");
  const double tl = block_mean(img, 1, 1, 2, 0), tr = block_mean(img, 5, 1, 2, 0);
  const double bl = block_mean(img, 1, 5, 2, 0), br = block_mean(img, 5, 5, 2, 0);
  EXPECT_NEAR(tl, br, 1e-6);
  EXPECT_NEAR(tr, bl, 1e-6);
  EXPECT_NEAR(std::min(tl, tr), 0, 1e-6);
  EXPECT_NEAR(std::max(tl, tr), 4, 1e-5);
}

// The medium filling a translucent shape is one medium: its parameters may not vary.
TEST(OpenPbrRender, TexturedInteriorIsRefused) {
  try {
    (void)parse_scene(R"({"shapes": [{"type": "sphere", "center": [0, 0, 0], "radius": 1, "material": {"type": "openpbr",
      "transmission_weight": 1, "transmission_color": 0.5, "transmission_depth": {"checker": [0.5, 1]}}}]})",
                      "s.json", "");
    FAIL() << "a textured transmission_depth was accepted";
  } catch (const std::exception& e) {
    EXPECT_NE(std::string(e.what()).find("one medium"), std::string::npos) << e.what();
  }
}

// A scattering interior is walked like a `subsurface` medium, whose limits it shares: a
// spectral render is refused with a line that says why.
TEST(OpenPbrRender, ScatteringInteriorIsRgbOnly) {
  const std::string scene = R"({"render": {"spectral": true}, "shapes": [{"type": "sphere", "center": [0, 1, 0], "radius": 1,
    "material": {"type": "openpbr", "transmission_weight": 1, "transmission_depth": 1, "transmission_scatter": 0.5}}]})";
  try {
    (void)render_text(scene);
    FAIL() << "a spectral render of a scattering openpbr interior was accepted";
  } catch (const std::exception& e) {
    EXPECT_NE(std::string(e.what()).find("scattering medium"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace gonio::render::test
