// Textures on `openpbr` parameters (issue 35 item 2; docs/scene-format.md, "Textures"):
// inside each square of a checker, the model a scene's material gives at the hit
// (Material::at) is the model of the uniform material with that square's value written in
// place and parsed as any material (material_from_json), in RGB, spectral and polarized
// form; the loader checks every texel by openpbr's own ranges.

#include <gtest/gtest.h>

#include <optional>
#include <string>

#include <nlohmann/json.hpp>

#include "gonio/material.h"
#include "gonio/polarization/polarized_bxdf.h"
#include "gonio/render/scene_loader.h"
#include "gonio/spectral_material.h"
#include "render_test_util.h"

namespace gonio::render::test {
namespace {

// Direction pairs over both hemispheres (reflection and transmission), off the planes of
// symmetry so that anisotropy and rotations show.
const Vec3 kDirs[] = {normalize(Vec3{0.3f, -0.2f, 0.9f}), normalize(Vec3{-0.5f, 0.4f, 0.6f}),
                      normalize(Vec3{0.8f, 0.1f, 0.2f}), normalize(Vec3{-0.1f, -0.7f, 0.5f}),
                      normalize(Vec3{0.2f, 0.3f, -0.8f})};

// The scene's one material: `material` on a sphere.
Material scene_material(const std::string& material) {
  const Scene s = parse_scene(R"({"shapes": [{"type": "sphere", "center": [0, 0, 0], "radius": 1, "material": )" +
                                  material + "}]}",
                              "test", "");
  return s.materials.at(0);
}

// `uniform` with `key` set to `value`, parsed as any material.
BxDF uniform_with(const std::string& uniform, const std::string& key, const nlohmann::json& value) {
  nlohmann::json d = nlohmann::json::parse(uniform);
  d[key] = value;
  return material_from_json(d);
}

void expect_same_rgb(const BxDF& a, const BxDF& b) {
  EXPECT_EQ(a.flags(), b.flags());
  for (const Vec3& wo : kDirs) {
    for (const Vec3& wi : kDirs) {
      const BSDFEval ea = a.eval(wo, wi), eb = b.eval(wo, wi);
      EXPECT_EQ(ea.f, eb.f) << "wo.z " << wo.z << " wi.z " << wi.z;
      EXPECT_EQ(ea.pdf, eb.pdf);
    }
    const auto sa = a.sample(wo, 0.6f, 0.3f, 0.7f), sb = b.sample(wo, 0.6f, 0.3f, 0.7f);
    ASSERT_EQ(sa.has_value(), sb.has_value());
    if (sa) {
      EXPECT_EQ(sa->weight, sb->weight);
    }
  }
}

void expect_same_spectral(const Material& m, const Vec2& uv, const BxDF& uniform) {
  std::optional<BxDF> scratch;
  SpectralScratch sa, sb;
  SampledWavelengths wa = SampledWavelengths::sample_visible(0.37f), wb = wa;
  const SpectralBxDF a = to_spectral(m.at(uv, scratch), m.spectra, wa, sa, m.textured_colours);
  const SpectralBxDF b = to_spectral(uniform, MaterialSpectra{}, wb, sb);
  for (const Vec3& wo : kDirs)
    for (const Vec3& wi : kDirs) {
      const auto ea = a.eval(wo, wi), eb = b.eval(wo, wi);
      for (int j = 0; j < SampledSpectrum::size(); ++j) EXPECT_EQ(ea.f[j], eb.f[j]) << "wavelength " << j;
      EXPECT_EQ(ea.pdf, eb.pdf);
    }
}

void expect_same_polarized(const BxDF& a, const BxDF& b) {
  const PolarizedBxDF pa(a), pb(b);
  for (const Vec3& wo : kDirs)
    for (const Vec3& wi : kDirs) EXPECT_EQ(pa.eval(wo, wi).f, pb.eval(wo, wi).f);
}

// A checker {a, b} on `key` of `uniform`: at uv in the even square the model of `uniform`
// with a, in the odd one with b, in every form; and the two differ.
void checker_test(const std::string& uniform, const std::string& key, const nlohmann::json& a, const nlohmann::json& b) {
  SCOPED_TRACE(key);
  nlohmann::json textured = nlohmann::json::parse(uniform);
  textured[key] = {{"checker", {a, b}}, {"uv_scale", 2}};
  const Material m = scene_material(textured.dump());
  ASSERT_EQ(m.textures.size(), 1u);
  const Vec2 even{0.2f, 0.3f}, odd{0.7f, 0.2f};  // floor(2u) + floor(2v): 0 and 1
  const BxDF ua = uniform_with(uniform, key, a), ub = uniform_with(uniform, key, b);
  std::optional<BxDF> scratch;
  expect_same_rgb(m.at(even, scratch), ua);
  expect_same_rgb(m.at(odd, scratch), ub);
  bool differ = false;  // the two values make a difference somewhere
  for (const Vec3& wo : kDirs)
    for (const Vec3& wi : kDirs) differ = differ || ua.eval(wo, wi).f != ub.eval(wo, wi).f;
  EXPECT_TRUE(differ);
  expect_same_spectral(m, even, ua);
  expect_same_spectral(m, odd, ub);
  expect_same_polarized(m.at(even, scratch), ua);
  expect_same_polarized(m.at(odd, scratch), ub);
}

// An EON base (base_diffuse_roughness > 0: the diffuse's normalisation is solved per
// material) under a coat and a thin film (its table and its albedo change solved too).
constexpr const char* kLayered =
    R"({"type": "openpbr", "base_diffuse_roughness": 0.5, "coat_weight": 0.4, "coat_roughness": 0.2,
        "thin_film_weight": 0.5, "thin_film_thickness": 0.4, "specular_roughness_anisotropy": 0.3,
        "specular_rotation": 0.1, "fuzz_weight": 0.3})";

// The same without the film (whose RGB table, made at every parse, is the slow part).
constexpr const char* kLayeredNoFilm =
    R"({"type": "openpbr", "base_diffuse_roughness": 0.5, "coat_weight": 0.4, "coat_roughness": 0.2,
        "specular_roughness_anisotropy": 0.3, "specular_rotation": 0.1, "fuzz_weight": 0.3})";

TEST(OpenPbrTextures, BaseColorCheckerIsTheUniformMaterialInEachSquare) {
  checker_test(kLayered, "base_color", {0.8, 0.2, 0.1}, {0.1, 0.4, 0.9});
}

// specular_roughness enters the quadratures: the smaller value's square must not reuse
// the ones solved for the larger (the loader's model is made with the largest values).
TEST(OpenPbrTextures, SpecularRoughnessCheckerIsTheUniformMaterialInEachSquare) {
  checker_test(kLayered, "specular_roughness", 0.2, 0.6);
}

TEST(OpenPbrTextures, OtherColoursAreTheUniformMaterialInEachSquare) {
  checker_test(kLayered, "coat_color", {0.9, 0.6, 0.3}, 1);
  checker_test(kLayeredNoFilm, "fuzz_color", {0.2, 0.9, 0.4}, {0.9, 0.1, 0.1});
  // A translucent base's tint (the index stays one number).
  checker_test(R"({"type": "openpbr", "transmission_weight": 0.8, "specular_roughness": 0.3})", "transmission_color",
               {0.9, 0.5, 0.2}, 0.7);
}

TEST(OpenPbrTextures, WeightsAndRoughnessesAreTheUniformMaterialInEachSquare) {
  // coat_weight sets the index under a film (whose table is then not used: docs): here
  // without one.
  checker_test(R"({"type": "openpbr", "base_diffuse_roughness": 0.5, "coat_roughness": 0.2})", "coat_weight", 0.1,
               0.9);
  checker_test(kLayeredNoFilm, "base_diffuse_roughness", 0, 0.8);
  checker_test(kLayered, "thin_film_weight", 0, 0.7);
  checker_test(kLayeredNoFilm, "base_metalness", 0.3, 1);
  checker_test(kLayeredNoFilm, "geometry_opacity", 0.5, 1);
}

TEST(OpenPbrTextures, TranslucentBaseIsTheUniformMaterialInEachSquare) {
  checker_test(R"({"type": "openpbr", "specular_roughness": 0.3})", "transmission_weight", 0.2, 0.9);
  // Thin-walled, where the index bounds no medium and may vary.
  checker_test(R"({"type": "openpbr", "transmission_weight": 0.5, "geometry_thin_walled": true})", "specular_ior",
               1.3, 1.8);
}

// A textured film thickness: where it is the loaded material's (the largest value) the
// film's RGB table is kept and the model is the uniform one; elsewhere the film is the
// Airy sum (its own tests: test_thin_film.cpp) at the channels' wavelengths, 650, 550 and
// 450 nm, of that thickness on the specular layer's index (docs/scene-format.md).
TEST(OpenPbrTextures, TexturedFilmThicknessReadsTheFilmAtTheChannelsWavelengths) {
  const std::string uniform = R"({"type": "openpbr", "coat_weight": 0.4, "thin_film_weight": 0.5})";
  nlohmann::json textured = nlohmann::json::parse(uniform);
  textured["thin_film_thickness"] = {{"checker", {0.3, 0.6}}, {"uv_scale", 2}};
  const Material m = scene_material(textured.dump());
  std::optional<BxDF> scratch;
  expect_same_rgb(m.at({0.7f, 0.2f}, scratch), uniform_with(uniform, "thin_film_thickness", 0.6));
  const auto& model = std::get<OpenPbrBxDF>(m.at({0.2f, 0.3f}, scratch).models());
  EXPECT_EQ(model.film.thickness, 300.0f);
  EXPECT_EQ(model.film.table, nullptr);
  EXPECT_EQ(model.film_w, 0.5f);
  const double lambda[3] = {650, 550, 450};
  for (double c : {1.0, 0.6, 0.2}) {
    const Color r = model.film.reflectance(Float(c), Color(model.spec_eta), Color(0));
    for (int ch = 0; ch < 3; ++ch)
      EXPECT_NEAR(r[ch], airy_film<double>(c, 1.4, 300, model.spec_eta, 0, lambda[ch]).R(), 1e-6) << c << " " << ch;
  }
}

// A render: a plane whose base_color is a checker of squares several pixels wide renders,
// pixel by pixel, exactly as the plane of the one colour or of the other (the same model at
// each hit, the same random numbers); only pixels across an edge are neither.
TEST(OpenPbrTextures, CheckerPlaneRendersAsTheUniformPlanesInEachSquare) {
  auto scene = [](const std::string& base_color) {
    return R"({"camera": {"position": [0, 3, 0], "look_at": [0, 0, 0], "up": [0, 0, -1], "fov": 40, "width": 48, "height": 48},
      "render": {"spp": 4, "seed": 3},
      "shapes": [{"type": "quad", "corner": [-5, 0, -5], "edge1": [0, 0, 10], "edge2": [10, 0, 0],
        "material": {"type": "openpbr", "base_diffuse_roughness": 0.5, "coat_weight": 0.5, "coat_roughness": 0.2,
                     "base_color": )" +
           base_color + R"(}}],
      "lights": [{"type": "point", "position": [0.4, 1.5, -0.3], "intensity": 5}],
      "environment": {"radiance": [0.2, 0.3, 0.4]}})";
  };
  const Image textured = render_text(scene(R"({"checker": [[0.8, 0.2, 0.1], [0.1, 0.4, 0.9]], "uv_scale": 10})"));
  const Image a = render_text(scene("[0.8, 0.2, 0.1]")), b = render_text(scene("[0.1, 0.4, 0.9]"));
  int as_a = 0, as_b = 0, neither = 0;
  for (int y = 0; y < textured.height(); ++y)
    for (int x = 0; x < textured.width(); ++x) {
      const Color t = textured.at(x, y);
      if (t == a.at(x, y)) ++as_a;
      else if (t == b.at(x, y)) ++as_b;
      else ++neither;
    }
  // 2.2 squares across the view of 48 pixels: about 2 × 48 × 4 pixels on edges.
  EXPECT_GT(as_a, 800);
  EXPECT_GT(as_b, 800);
  EXPECT_LT(neither, 48 * 48 / 4);
}

std::string texture_load_error(const std::string& material) {
  try {
    scene_material(material);
  } catch (const InputError& e) {
    return e.what();
  }
  return "(no error)";
}

TEST(OpenPbrTextures, LoaderChecksEachTexelByOpenPbrsRanges) {
  const std::string bad_colour =
      texture_load_error(R"({"type": "openpbr", "base_color": {"checker": [0.5, [0.2, 1.5, 0.2]]}})");
  EXPECT_NE(bad_colour.find("/shapes/0/material/base_color/checker/1: value [0.2, 1.5, 0.2] is out of range "
                            "(openpbr: base_color must be in [0, 1], got 1.5)"),
            std::string::npos)
      << bad_colour;
  const std::string bad_number =
      texture_load_error(R"({"type": "openpbr", "thin_film_thickness": {"checker": [0.3, 12]}})");
  EXPECT_NE(bad_number.find("/shapes/0/material/thin_film_thickness/checker/1: value 12 is out of range "
                            "(openpbr: thin_film_thickness must be in [0, 10] um, got 12)"),
            std::string::npos)
      << bad_number;
  // Not a texture: a flag, and the glass's index behind a translucent base.
  const std::string flag = texture_load_error(R"({"type": "openpbr", "geometry_thin_walled": {"checker": [0, 1]}})");
  EXPECT_NE(flag.find("/shapes/0/material/geometry_thin_walled: cannot be a texture"), std::string::npos) << flag;
  for (const char* key : {"specular_ior", "specular_weight"}) {
    nlohmann::json d = {{"type", "openpbr"}, {"transmission_weight", 0.5}, {key, {{"checker", {1.3, 1.5}}}}};
    const std::string medium = texture_load_error(d.dump());
    EXPECT_NE(medium.find(std::string("/shapes/0/material/") + key + ": cannot be a texture here"), std::string::npos)
        << medium;
    EXPECT_NE(medium.find("transmission_weight is 0"), std::string::npos) << medium;
  }
}

}  // namespace
}  // namespace gonio::render::test
