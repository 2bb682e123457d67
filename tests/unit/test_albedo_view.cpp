// The albedo gonio reports is the lecture's ρ_hd(ωo) of the view direction (SPEC §3,
// issue 55 §3): for a model that is not reciprocal (OpenPBR's view-dependent coat and
// fuzz) it differs from the light's, which follows apart. White furnaces, the limit at
// θ = 90°, the compensation of anisotropic roughness (issue 55 §4) and the OpenPBR coat's
// relative specular index (issue 56 §1). Expected values are closed forms (a white furnace
// is 1) or numerical integrations of f written here.

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <string>

#include "gonio/material.h"
#include "gonio/math/warp.h"
#include "gonio/reflectance.h"
#include "gonio/validate.h"

namespace gonio {
namespace {

Vec3 view_at(double theta_deg, double phi_deg = 0) {
  const double t = theta_deg * kPiD / 180, p = phi_deg * kPiD / 180;
  return {Float(std::sin(t) * std::cos(p)), Float(std::sin(t) * std::sin(p)), Float(std::cos(t))};
}

double channel_max(const Color& c) { return double(c.max_component()); }
double channel_min(const Color& c) { return double(std::min({c[0], c[1], c[2]})); }

// ∫ f(wo, wi) cos θi dωi over the upper hemisphere by an n × n midpoint grid of
// cosine-weighted directions (density cos θ / π, so each point weighs π f / n²): from f
// alone, not from the model's sampling or its albedo tables.
Color reflectance_by_quadrature(const BxDF& m, const Vec3& wo, int n) {
  double sum[3] = {};
  for (int a = 0; a < n; ++a)
    for (int b = 0; b < n; ++b) {
      const Vec3 wi = square_to_cosine_hemisphere((Float(a) + Float(0.5)) / Float(n), (Float(b) + Float(0.5)) / Float(n));
      if (!(wi.z > 0)) continue;
      const Color f = m.f(wo, wi, TransportMode::Radiance);
      for (int c = 0; c < 3; ++c) sum[c] += double(f[c]);
    }
  Color r;
  for (int c = 0; c < 3; ++c) r[c] = Float(sum[c] * kPiD / (double(n) * n));
  return r;
}

// Issue 55 §3: a white coat over a white base, and a white fuzz. The light's albedo (light
// arriving along wo) of OpenPBR's view-dependent layering exceeds 1 at grazing (1.352 and
// 1.391 at 85°); the view's, which camera paths depend on, is 1.
TEST(ViewAlbedo, OpenPbrWhiteCoatAndFuzzFurnacesFromTheView) {
  const char* cases[] = {
      R"({"type":"openpbr","base_color":1,"coat_weight":1,"coat_roughness":0.2,"specular_roughness":0.3})",
      R"({"type":"openpbr","base_color":1,"fuzz_weight":1})",
  };
  for (const char* text : cases) {
    const BxDF m = parse_material(text);
    ASSERT_FALSE(m.nonreciprocal_reason().empty()) << text;
    for (double theta : {0.0, 45.0, 75.0, 85.0}) {
      SCOPED_TRACE(std::string(text) + " at " + std::to_string(theta));
      const AlbedoEstimate e = directional_albedo(m, view_at(theta), {200'000, 3});
      EXPECT_NEAR(channel_max(e.albedo), 1, 0.01);
      EXPECT_NEAR(channel_min(e.albedo), 1, 0.01);
      EXPECT_TRUE(channel_max(e.transmittance) == 0);
      ASSERT_TRUE(e.light.has_value());
      // The light's figure is the other one: above 1.1 at 85° (the issue's 1.35 and 1.39).
      if (theta == 85) {
        EXPECT_GT(channel_min(e.light->albedo), 1.1);
      }
    }
  }
}

// A coat over a translucent base (transmission_weight 1): reflectance plus the transmittance
// with the refraction's radiance scaling removed is 1 from the view.
TEST(ViewAlbedo, OpenPbrCoatOverGlassFurnaceFromTheView) {
  const BxDF m = parse_material(
      R"({"type":"openpbr","transmission_weight":1,"coat_weight":1,"coat_roughness":0.2,"specular_roughness":0.3})");
  for (double theta : {0.0, 45.0, 75.0, 85.0}) {
    SCOPED_TRACE(theta);
    const AlbedoEstimate e = directional_albedo(m, view_at(theta), {200'000, 5});
    EXPECT_GT(channel_min(e.transmittance), 0);
    EXPECT_NEAR(channel_max(e.albedo), 1, 0.01);
    EXPECT_NEAR(channel_min(e.albedo), 1, 0.01);
  }
}

// A reciprocal model reports no light-side figure (it is the view's).
TEST(ViewAlbedo, ReciprocalModelsHaveOneFigure) {
  const AlbedoEstimate e = directional_albedo(parse_material(R"({"type":"roughdielectric","alpha":0.3})"), view_at(40),
                                              {20'000, 1});
  EXPECT_FALSE(e.light.has_value());
  const AlbedoEstimate h = hemispherical_albedo(parse_material(R"({"type":"openpbr","fuzz_weight":1})"), false, {20'000, 1});
  EXPECT_TRUE(h.light.has_value());
}

// Issue 55 §3: at θ = 90° exactly every albedo is reported as its limit θ → 90°: a white
// rough metal does not drop to 0 at its last point while a smooth one stays at 1.
TEST(ViewAlbedo, NinetyDegreesIsTheLimit) {
  const char* cases[] = {
      R"({"type":"roughconductor","alpha":0.3,"fresnel":"schlick","f0":1,"multiscatter":true})",
      R"({"type":"openpbr","base_metalness":1,"base_color":1,"specular_color":1})",
      R"({"type":"openpbr"})",
  };
  for (const char* text : cases) {
    SCOPED_TRACE(text);
    const BxDF m = parse_material(text);
    // The tool's wo at 90°: cos(π/2) in double, 6e-17, not 0.
    const Vec3 wo90{1, 0, Float(std::cos(kPiD / 2))};
    const AlbedoEstimate at90 = directional_albedo(m, wo90, {100'000, 7});
    const AlbedoEstimate near = directional_albedo(m, view_at(89.999), {100'000, 7});
    EXPECT_GT(channel_max(at90.albedo), 0.5);
    EXPECT_NEAR(channel_max(at90.albedo), channel_max(near.albedo), 0.02);
  }
}

// Issue 55 §4: Kulla–Conty compensation for anisotropic roughness. A white metal returns 1
// at any anisotropy, by a quadrature of f written here, at several angles and azimuths.
TEST(ViewAlbedo, AnisotropicWhiteMetalFurnace) {
  const char* cases[] = {
      R"({"type":"roughconductor","alpha":[0.1,0.5],"fresnel":"schlick","f0":1,"multiscatter":true})",
      R"({"type":"roughconductor","alpha":[0.6,0.15],"fresnel":"schlick","f0":1,"multiscatter":true})",
      R"({"type":"openpbr","base_metalness":1,"base_color":1,"specular_color":1,"specular_roughness":0.6,"specular_roughness_anisotropy":0.5})",
      R"({"type":"openpbr","base_metalness":1,"base_color":1,"specular_color":1,"specular_roughness":0.7,"specular_roughness_anisotropy":0.8})",
  };
  for (const char* text : cases) {
    const BxDF m = parse_material(text);
    for (double theta : {0.0, 45.0, 75.0})
      for (double phi : {0.0, 60.0}) {
        SCOPED_TRACE(std::string(text) + " theta " + std::to_string(theta) + " phi " + std::to_string(phi));
        const Color r = reflectance_by_quadrature(m, view_at(theta, phi), 384);
        EXPECT_NEAR(channel_min(r), 1, 0.01);
        EXPECT_NEAR(channel_max(r), 1, 0.01);
      }
  }
}

// Issue 56 §1: under a full coat the specular layer reflects at the index n_b/n_c (SPEC-OPB
// eq. `specular_ior_ratio_with_tir_fix`): with specular_ior = coat_ior that inner interface
// does not reflect, so a black base under it is the same as one without a specular layer
// (specular_weight 0), and with another specular_ior it is not.
TEST(ViewAlbedo, OpenPbrCoatEqualIndexHidesTheInnerInterface) {
  const std::string coat = R"("type":"openpbr","base_color":0,"coat_weight":1,"coat_ior":1.7,"coat_roughness":0.3,)"
                           R"("specular_roughness":0.25)";
  const BxDF same = parse_material("{" + coat + R"(,"specular_ior":1.7})");
  const BxDF none = parse_material("{" + coat + R"(,"specular_ior":1.7,"specular_weight":0})");
  const BxDF other = parse_material("{" + coat + R"(,"specular_ior":1.5})");
  double worst_same = 0, largest_other = 0;
  for (double to : {0.0, 30.0, 60.0})
    for (double ti : {10.0, 35.0, 70.0}) {
      const Vec3 wo = view_at(to), wi = view_at(ti, 180);
      const double a = channel_max(same.f(wo, wi, TransportMode::Radiance));
      const double b = channel_max(none.f(wo, wi, TransportMode::Radiance));
      const double c = channel_max(other.f(wo, wi, TransportMode::Radiance));
      worst_same = std::max(worst_same, std::abs(a - b) / std::max(b, 1e-6));
      largest_other = std::max(largest_other, std::abs(c - b) / std::max(b, 1e-6));
    }
  EXPECT_LT(worst_same, 1e-5);
  EXPECT_GT(largest_other, 1e-3);
}

// reciprocal_layering (gonio's extension): the coat passes reciprocity; the fuzz lobe stays
// view-keyed (not applicable). OpenPBR's default form is not reciprocal.
TEST(ViewAlbedo, ReciprocalLayeringMakesTheCoatReciprocal) {
  const std::string coat = R"("type":"openpbr","base_color":[0.9,0.6,0.3],"coat_weight":1,"coat_roughness":0.2)";
  const ValidationOptions opt{1, 0.25};
  const PropertyResult recip = check_reciprocity(parse_material("{" + coat + R"(,"reciprocal_layering":true})"), opt);
  EXPECT_TRUE(recip.applicable);
  EXPECT_TRUE(recip.pass) << recip.detail;
  EXPECT_FALSE(check_reciprocity(parse_material("{" + coat + "}"), opt).applicable);
  const BxDF fuzz = parse_material(R"({"type":"openpbr","fuzz_weight":1,"coat_weight":1,"reciprocal_layering":true})");
  EXPECT_FALSE(fuzz.nonreciprocal_reason().empty());
}

// Issue 56 §2: a thin film of extreme index and thickness over a white base, very near
// grazing. The film changes the rough specular lobe's albedo fastest there; read from the
// film table's first node (μ = 1/128), the diffuse under it took the difference as its own
// (albedo 1.0055 at 89.95° with the default base colour, 1.009 with a white one). A white
// furnace may not exceed 1 (the allowance: 4σ and the tables' 0.1 %).
TEST(ViewAlbedo, ExtremeThinFilmHoldsTheFurnaceAtGrazing) {
  const BxDF m = parse_material(
      R"({"type":"openpbr","base_color":1,"thin_film_weight":1,"thin_film_ior":10000,"thin_film_thickness":10})");
  for (double theta : {89.0, 89.8, 89.95, 89.99, 90.0}) {
    SCOPED_TRACE(theta);
    const AlbedoEstimate e = directional_albedo(m, view_at(theta), {200'000, 7});
    for (int c = 0; c < 3; ++c) EXPECT_LE(double(e.albedo[c]), 1 + 4 * double(e.se_albedo[c]) + 1e-3) << c;
  }
}

}  // namespace
}  // namespace gonio
