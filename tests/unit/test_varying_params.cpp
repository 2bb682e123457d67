// Spatially varying parameters (material.h): with_params must build exactly the model
// material_from_json builds from the same description with the new value, for every
// parameter of every type that may vary; that keeps the parser the one source of the
// parameters' meaning and ranges.

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "gonio/material.h"
#include "gonio/material_types.h"

namespace gonio {
namespace {

using nlohmann::json;

struct VaryCase {
  const char* description;  // the model before
  const char* key;
  int entry;                // index into "alpha": [ax, ay], else -1
  MaterialParam param;
  json value;               // the new value, as JSON
};

Color to_color(const json& v) {
  if (v.is_number()) return Color(v.get<Float>());
  return Color(v[0].get<Float>(), v[1].get<Float>(), v[2].get<Float>());
}

void expect_same_model(const BxDF& a, const BxDF& b) {
  const Vec3 dirs[] = {normalize(Vec3{0.3f, -0.2f, 0.9f}), normalize(Vec3{-0.5f, 0.4f, 0.6f}),
                       normalize(Vec3{0.8f, 0.1f, 0.2f}), normalize(Vec3{-0.1f, -0.7f, 0.5f}),
                       normalize(Vec3{0.2f, 0.3f, -0.8f})};
  EXPECT_EQ(a.flags(), b.flags());
  EXPECT_EQ(a.is_isotropic(), b.is_isotropic());
  for (const Vec3& wo : dirs) {
    for (const Vec3& wi : dirs) {
      const BSDFEval ea = a.eval(wo, wi), eb = b.eval(wo, wi);
      EXPECT_EQ(ea.f, eb.f);
      EXPECT_EQ(ea.pdf, eb.pdf);
    }
    for (Float u : {0.1f, 0.45f, 0.8f}) {
      const auto sa = a.sample(wo, u, 1 - u, u * u), sb = b.sample(wo, u, 1 - u, u * u);
      ASSERT_EQ(sa.has_value(), sb.has_value());
      if (!sa) continue;
      EXPECT_EQ(sa->wi.x, sb->wi.x);
      EXPECT_EQ(sa->wi.z, sb->wi.z);
      EXPECT_EQ(sa->weight, sb->weight);
      EXPECT_EQ(sa->pdf, sb->pdf);
    }
  }
}

MaterialParam opb(const char* key) { return varying_param("openpbr", key).value(); }

// Each case: with_params of the model before is the model parsed with the new value.
void expect_each_case(const std::vector<VaryCase>& cases) {
  for (const auto& c : cases) {
    SCOPED_TRACE(std::string(c.description) + " with " + c.key + " = " + c.value.dump());
    const json before = json::parse(c.description);
    json after = before;
    if (c.entry < 0) after[c.key] = c.value;
    else after[c.key][static_cast<size_t>(c.entry)] = c.value;
    ASSERT_EQ(varying_param(before["type"].get<std::string>(), c.key),
              c.entry < 0 ? c.param : MaterialParam::Alpha);
    const ParamValue v{c.param, to_color(c.value)};
    expect_same_model(with_params(material_from_json(before), {&v, 1}), material_from_json(after));
    // The probe passes the parser on its own.
    json probe = before;
    if (c.entry < 0) probe[c.key] = material_param_info(c.param).probe;
    else probe[c.key][static_cast<size_t>(c.entry)] = material_param_info(c.param).probe;
    EXPECT_NO_THROW(material_from_json(probe));
  }
}

TEST(VaryingParams, WithParamsEqualsParsingTheNewValue) {
  using MP = MaterialParam;
  const std::vector<VaryCase> cases = {
      {R"({"type":"diffuse","reflectance":0.3})", "reflectance", -1, MP::Reflectance, {0.1, 0.5, 0.9}},
      {R"({"type":"mirror","reflectance":0.3})", "reflectance", -1, MP::Reflectance, 0.7},
      {R"({"type":"conductor","eta":[0.2,0.4,1.3],"k":[3,2.5,2]})", "eta", -1, MP::Eta, {1.5, 1.2, 0.9}},
      {R"({"type":"conductor","eta":[0.2,0.4,1.3],"k":[3,2.5,2]})", "k", -1, MP::K, {1, 2, 3}},
      // With Schlick, F0 follows the index.
      {R"({"type":"conductor","fresnel":"schlick","eta":1.5,"k":1})", "eta", -1, MP::Eta, 2.5},
      {R"({"type":"conductor","fresnel":"schlick","f0":0.5})", "f0", -1, MP::F0, {0.9, 0.6, 0.3}},
      {R"({"type":"roughconductor","material":"Au","alpha":0.3,"multiscatter":true})", "alpha", -1, MP::Alpha, 0.6},
      {R"({"type":"roughconductor","eta":[0.2,0.4,1.3],"k":[3,2.5,2],"alpha":0.3,"multiscatter":true})", "eta", -1, MP::Eta, {1.1, 0.5, 0.3}},
      {R"({"type":"roughconductor","eta":[0.2,0.4,1.3],"k":[3,2.5,2],"alpha":0.3,"multiscatter":true})", "k", -1, MP::K, 0.5},
      {R"({"type":"roughconductor","fresnel":"schlick","f0":0.9,"alpha":0.3,"multiscatter":true})", "f0", -1, MP::F0, {0.3, 0.5, 0.7}},
      {R"({"type":"roughconductor","material":"Cu","alpha":[0.2,0.4],"distribution":"beckmann"})", "alpha", 0, MP::AlphaX, 0.5},
      {R"({"type":"roughconductor","material":"Cu","alpha":[0.2,0.4]})", "alpha", 1, MP::AlphaY, 0.05},
      // Down to smooth: the multiple-scattering lobe goes, as the parser leaves it out.
      {R"({"type":"roughconductor","material":"Au","alpha":0.3,"multiscatter":true})", "alpha", -1, MP::Alpha, 0.0005},
      {R"({"type":"roughdielectric","alpha":0.3,"eta":1.4})", "alpha", -1, MP::Alpha, 0.1},
      {R"({"type":"orennayar","reflectance":0.5,"sigma":20})", "sigma", -1, MP::Sigma, 40},
      {R"({"type":"orennayar","reflectance":0.5,"sigma":20,"model":"full"})", "reflectance", -1, MP::Reflectance, {0.2, 0.4, 0.6}},
      {R"({"type":"phong","kd":0.3,"ks":0.2,"exponent":20})", "kd", -1, MP::Kd, {0.1, 0.5, 0.7}},
      {R"({"type":"phong","kd":0.3,"ks":0.2,"exponent":20})", "ks", -1, MP::Ks, 0.6},
      {R"({"type":"phong","kd":0.3,"ks":0.2,"exponent":20})", "exponent", -1, MP::Exponent, 150},
      {R"({"type":"blinnphong","kd":0.3,"ks":0.2,"exponent":20})", "exponent", -1, MP::Exponent, 3},
      {R"({"type":"blinnphong","kd":0.3,"ks":0.2,"exponent":20})", "ks", -1, MP::Ks, {0.1, 0.3, 0.5}},
      {R"({"type":"ward","kd":0.3,"ks":0.2,"alpha":0.2})", "alpha", -1, MP::Alpha, 0.4},
      {R"({"type":"ward","kd":0.3,"ks":0.2,"alpha":[0.2,0.3]})", "alpha", 1, MP::AlphaY, 0.05},
      {R"({"type":"ward","kd":0.3,"ks":0.2,"alpha":0.2})", "kd", -1, MP::Kd, 0.6},
      {R"({"type":"ashikhminshirley","rd":0.3,"rs":0.2,"nu":10,"nv":100})", "rd", -1, MP::Rd, {0.6, 0.1, 0.2}},
      {R"({"type":"ashikhminshirley","rd":0.3,"rs":0.2,"nu":10,"nv":100})", "rs", -1, MP::Rs, 0.05},
      {R"({"type":"ashikhminshirley","rd":0.3,"rs":0.2,"nu":10,"nv":100})", "nu", -1, MP::Nu, 500},
      {R"({"type":"ashikhminshirley","rd":0.3,"rs":0.2,"nu":10,"nv":100})", "nv", -1, MP::Nv, 2},
      {R"({"type":"plastic","reflectance":0.3,"alpha":0.2})", "reflectance", -1, MP::Reflectance, {0.8, 0.2, 0.1}},
      {R"({"type":"plastic","reflectance":0.3,"alpha":0.2})", "alpha", -1, MP::Alpha, 0.5},
      {R"({"type":"sheen","color":0.3,"roughness":0.4})", "color", -1, MP::SheenColor, {0.9, 0.5, 0.1}},
  };
  expect_each_case(cases);
}

// openpbr, made again from its parameters: colours, and inputs of its quadratures (an EON
// base's normalisation; with a film, the film's albedo change, its table kept since the
// index under it is unchanged).
TEST(VaryingParams, OpenPbrWithParamsEqualsParsingTheNewValue) {
  constexpr const char* kOpb =
      R"({"type":"openpbr","base_diffuse_roughness":0.6,"coat_weight":0.5,"coat_roughness":0.1,"subsurface_weight":0.3,)"
      R"("fuzz_weight":0.2,"specular_roughness":0.2})";
  constexpr const char* kFilm =
      R"({"type":"openpbr","base_diffuse_roughness":0.6,"thin_film_weight":0.4,"thin_film_thickness":0.3})";
  expect_each_case({
      {kOpb, "specular_color", -1, opb("specular_color"), {0.9, 0.7, 0.5}},
      {kOpb, "subsurface_color", -1, opb("subsurface_color"), {0.1, 0.7, 0.5}},
      {kOpb, "specular_roughness", -1, opb("specular_roughness"), 0.7},
      {kOpb, "coat_roughness", -1, opb("coat_roughness"), 0.5},
      {kOpb, "coat_ior", -1, opb("coat_ior"), 1.3},
      {kOpb, "base_diffuse_roughness", -1, opb("base_diffuse_roughness"), 0.1},
      {kOpb, "fuzz_roughness", -1, opb("fuzz_roughness"), 0.1},
      {kFilm, "specular_roughness", -1, opb("specular_roughness"), 0.6},
      {kFilm, "thin_film_weight", -1, opb("thin_film_weight"), 0.9},
  });
}

TEST(VaryingParams, OnlyModelParametersMayVary) {
  EXPECT_EQ(varying_param("roughconductor", "alpha"), MaterialParam::Alpha);
  EXPECT_EQ(varying_param("diffuse", "reflectance"), MaterialParam::Reflectance);
  EXPECT_FALSE(varying_param("roughconductor", "fresnel"));
  EXPECT_FALSE(varying_param("roughconductor", "multiscatter"));
  EXPECT_FALSE(varying_param("dielectric", "eta"));
  EXPECT_FALSE(varying_param("plastic", "eta"));
  EXPECT_FALSE(varying_param("blend", "weight"));
  EXPECT_FALSE(varying_param("nosuchtype", "alpha"));
  EXPECT_EQ(varying_param_keys("phong"), "kd, ks, exponent");
  EXPECT_EQ(varying_param_keys("dielectric"), "");
  // Every type but dielectric, blend, layered, measured and subsurface (a medium, whose
  // boundary's index may not vary for the reason dielectric's may not) has something that
  // may vary.
  for (auto type : material_type_names())
    EXPECT_EQ(varying_param_keys(type).empty(),
              type == "dielectric" || type == "blend" || type == "layered" || type == "measured" ||
                  type == "subsurface" || type == "thindielectric" || type == "hair" || type == "chiang_hair_bsdf" ||
                  // MaterialX's pbrlib nodes: their inputs vary through the document's node
                  // graph (issue 57), not as a scene's textures; rgl is its table.
                  type == "rgl" || type == "oren_nayar_diffuse_bsdf" || type == "conductor_bsdf" ||
                  type == "dielectric_bsdf" || type == "sheen_bsdf" || type == "mix" || type == "add" ||
                  type == "multiply" || type == "layer")
        << type;
}

// openpbr: every number and colour of the registry (material_types.cpp, the table `gonio
// materials` shows) may vary, each as its own parameter of the right kind, and nothing else
// (geometry_thin_walled, a flag).
TEST(VaryingParams, EveryOpenPbrNumberAndColourMayVary) {
  const MaterialTypeSpec* t = find_material_type("openpbr");
  ASSERT_NE(t, nullptr);
  std::vector<MaterialParam> seen;
  for (const ParamSpec& p : t->params) {
    SCOPED_TRACE(p.name);
    const auto v = varying_param("openpbr", p.name);
    if (p.kind != ParamKind::Number && p.kind != ParamKind::Colour) {
      EXPECT_FALSE(v);
      continue;
    }
    ASSERT_TRUE(v);
    EXPECT_EQ(material_param_info(*v).key, p.name);
    EXPECT_EQ(material_param_info(*v).scalar, p.kind == ParamKind::Number);
    EXPECT_TRUE(p.range.contains(material_param_info(*v).probe));
    EXPECT_EQ(std::count(seen.begin(), seen.end(), *v), 0);
    seen.push_back(*v);
  }
  EXPECT_EQ(seen.size(), kGltfPbrFirst - size_t(MaterialParam::OpenPbrFirst));
  EXPECT_FALSE(varying_param("openpbr", "geometry_thin_walled"));
  // The medium's index: not behind a translucent base, unless thin-walled.
  const json glass = {{"type", "openpbr"}, {"transmission_weight", 0.5}};
  EXPECT_TRUE(varying_param_refused(glass, "specular_ior"));
  EXPECT_TRUE(varying_param_refused(glass, "specular_weight"));
  EXPECT_FALSE(varying_param_refused(glass, "coat_ior"));
  json thin = glass;
  thin["geometry_thin_walled"] = true;
  EXPECT_FALSE(varying_param_refused(thin, "specular_ior"));
  EXPECT_FALSE(varying_param_refused(json{{"type", "openpbr"}}, "specular_ior"));
  EXPECT_FALSE(varying_param_refused(json{{"type", "roughconductor"}}, "alpha"));
}

}  // namespace
}  // namespace gonio
