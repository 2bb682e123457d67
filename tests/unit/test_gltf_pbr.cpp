// gltf_pbr (include/gonio/bxdf/gltf_pbr.h) against numbers made here without the model's
// code: the glTF 2.0 Appendix B BRDF and the KHR_materials_* formulas written out again in
// double, in the specifications' own forms (Khronos's V_GGX and D_GGX, not gonio's Λ and
// G2), the Charlie sheen's albedo by this file's quadrature, Walter et al. 2007's eq. 21 for
// the volume's refraction; and the validator's sampling checks (χ², pdf integral,
// consistency, reciprocity, finiteness) on the extensions. docs/gltf_pbr.md publishes the
// white furnace figures computed by the quadrature below.

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include "../test_common.h"
#include "test_scale.h"
#include "gonio/bxdf.h"
#include "gonio/material.h"
#include "gonio/rng.h"
#include "gonio/validate.h"

namespace gonio {
namespace gltf_pbr_test {

struct D3 {
  double x, y, z;
};
D3 d3(const Vec3& v) { return {v.x, v.y, v.z}; }
double dotd(const D3& a, const D3& b) { return a.x * b.x + a.y * b.y + a.z * b.z; }
D3 unit(const D3& a) {
  const double l = std::sqrt(dotd(a, a));
  return {a.x / l, a.y / l, a.z / l};
}

// The Appendix B / extension formulas, one channel, isotropic or anisotropic (tangent frame
// turned by `rot`), both directions above the surface.
struct Ref {
  double base = 1, metallic = 1, roughness = 1, specular = 1, specular_color = 1, ior = 1.5;
  double clearcoat = 0, clearcoat_roughness = 0, aniso = 0, rot = 0;
  double sheen = 0, sheen_roughness = 0.5, sheen_e_o = 0, sheen_e_i = 0;  // E(μo), E(μi) from this file's quadrature
  double transmission = 0, dt = 0, dt_color = 1;
};

double schlick_w(double c) { return std::pow(1 - c, 5); }
// Khronos App. B.3.3: D = α² / (π (NdotH² (α² − 1) + 1)²); KHR_materials_anisotropy's form
// 1 / (π αt αb ((T·H/αt)² + (B·H/αb)² + (N·H)²)²).
double d_ggx(const D3& h, double at, double ab) {
  const double e = (h.x / at) * (h.x / at) + (h.y / ab) * (h.y / ab) + h.z * h.z;
  return 1 / (kPiD * at * ab * e * e);
}
// App. B.3.2's height-correlated V (= G / (4 NdotL NdotV)), anisotropic as KHR_materials_anisotropy.
double v_ggx(const D3& v, const D3& l, double at, double ab) {
  const double gv = l.z * std::sqrt(at * at * v.x * v.x + ab * ab * v.y * v.y + v.z * v.z);
  const double gl = v.z * std::sqrt(at * at * l.x * l.x + ab * ab * l.y * l.y + l.z * l.z);
  return 0.5 / (gv + gl);
}
D3 turn(const D3& w, double r) {
  return {std::cos(r) * w.x + std::sin(r) * w.y, -std::sin(r) * w.x + std::cos(r) * w.y, w.z};
}
// Estevez & Kulla 2017 / KHR_materials_sheen, written again.
double charlie(const D3& v, const D3& l, double a) {
  const D3 h = unit({v.x + l.x, v.y + l.y, v.z + l.z});
  const double d = (2 + 1 / a) * std::pow(1 - h.z * h.z, 0.5 / a) / (2 * kPiD);
  const auto lf = [a](double x) {
    const double t = (1 - a) * (1 - a);
    return (21.5473 + (25.3245 - 21.5473) * t) / (1 + (3.82987 + (3.32435 - 3.82987) * t) * std::pow(x, 0.19823 + (0.16801 - 0.19823) * t)) +
           (-1.97760 + (-1.27393 + 1.97760) * t) * x + (-4.32054 + (-4.85967 + 4.32054) * t);
  };
  const auto lam = [&](double c) { return c < 0.5 ? std::exp(lf(c)) : std::exp(2 * lf(0.5) - lf(1 - c)); };
  return d / ((1 + lam(v.z) + lam(l.z)) * 4 * v.z * l.z);
}

double ref_reflection(const Ref& p, const D3& v, const D3& l) {
  const D3 h = unit({v.x + l.x, v.y + l.y, v.z + l.z});
  const double c = dotd(v, h);
  const double alpha = std::max(p.roughness * p.roughness, 2e-3);
  const double at = alpha + (1 - alpha) * p.aniso * p.aniso, ab = alpha;
  const D3 tv = turn(v, p.rot), tl = turn(l, p.rot), th = turn(h, p.rot);
  const double spec = v_ggx(tv, tl, at, ab) * d_ggx(th, at, ab);
  const double f0 = std::min(std::pow((p.ior - 1) / (p.ior + 1), 2) * p.specular_color, 1.0) * p.specular;
  const double fd = f0 + (p.specular - f0) * schlick_w(c);
  const double dielectric = fd * spec + (1 - fd) * (1 - p.transmission) * (1 - p.dt) * p.base / kPiD;
  const double metal = (p.base + (1 - p.base) * schlick_w(c)) * spec;
  double f = (1 - p.metallic) * dielectric + p.metallic * metal;
  if (p.sheen > 0) {
    const double a = std::max(p.sheen_roughness, 0.07);
    f = f * std::min(1 - p.sheen * p.sheen_e_o, 1 - p.sheen * p.sheen_e_i) + p.sheen * charlie(v, l, a);
  }
  if (p.clearcoat > 0) {
    const double ac = std::max(p.clearcoat_roughness * p.clearcoat_roughness, 2e-3);
    const double fc = p.clearcoat * (0.04 + 0.96 * schlick_w(c));
    f = f * (1 - fc) + fc * v_ggx(v, l, ac, ac) * d_ggx(h, ac, ac);
  }
  return f;
}

// E(μ) of the Charlie lobe by Gauss–Legendre in cos θi and φ.
double charlie_albedo_quadrature(double mu, double a) {
  std::vector<double> x, wx, y, wy;
  gauss_legendre(64, 0, 1, x, wx);
  gauss_legendre(64, 0, kPiD, y, wy);
  const D3 v{std::sqrt(1 - mu * mu), 0, mu};
  double s = 0;
  for (size_t i = 0; i < x.size(); ++i)
    for (size_t j = 0; j < y.size(); ++j) {
      const double si = std::sqrt(1 - x[i] * x[i]);
      s += 2 * wx[i] * wy[j] * charlie(v, {si * std::cos(y[j]), si * std::sin(y[j]), x[i]}, a) * x[i];
    }
  return s;
}

Vec3 dir(double mu, double phi) {
  const double s = std::sqrt(std::max(0.0, 1 - mu * mu));
  return Vec3{Float(s * std::cos(phi)), Float(s * std::sin(phi)), Float(mu)};
}

const GltfPbrBxDF& model_of(const BxDF& b) { return std::get<GltfPbrBxDF>(b.models()); }

ValidationOptions quick() {
  ValidationOptions o;
  o.scale = std::min(0.1, double(test::scaled(1000000, 1)) / 1e6);
  return o;
}

TEST(GltfPbr, ParserTakesMaterialXsDefaultsAndTheRegistrysRanges) {
  const BxDF b = parse_material(R"({"type":"gltf_pbr"})");
  const GltfPbrParams<Color>& p = model_of(b).params;
  // MaterialX 1.39 ND_gltf_pbr_surfaceshader's values.
  EXPECT_EQ(p.base_color, Color(1));
  EXPECT_EQ(p.metallic, 1);
  EXPECT_EQ(p.roughness, 1);
  EXPECT_EQ(p.specular, 1);
  EXPECT_FLOAT_EQ(p.ior, 1.5f);
  EXPECT_FLOAT_EQ(p.iridescence_ior, 1.3f);
  EXPECT_EQ(p.iridescence_thickness, 100);
  EXPECT_EQ(p.sheen_color, Color(0));
  EXPECT_EQ(p.alpha_mode, 0);
  EXPECT_FLOAT_EQ(p.alpha_cutoff, 0.5f);
  EXPECT_EQ(p.attenuation_color, Color(1));
  EXPECT_EQ(p.emissive_strength, 1);
  EXPECT_THROW(parse_material(R"({"type":"gltf_pbr","roughness":1.5})"), InputError);
  EXPECT_THROW(parse_material(R"({"type":"gltf_pbr","ior":0.9})"), InputError);
  EXPECT_THROW(parse_material(R"({"type":"gltf_pbr","alpha_mode":1.5})"), InputError);
  EXPECT_THROW(parse_material(R"({"type":"gltf_pbr","alpha_mode":3})"), InputError);
  EXPECT_THROW(parse_material(R"({"type":"gltf_pbr","base_colour":1})"), InputError);
  try {
    parse_material(R"({"type":"gltf_pbr","iridescence":0.5})");
    FAIL() << "iridescence accepted";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("iridescence"), std::string::npos) << e.what();
  }
}

// The model against the formulas above at random pairs, for the core and each reflecting
// extension (the sheen's E from this file's quadrature).
TEST(GltfPbr, ReflectionIsAppendixBWithTheExtensions) {
  struct Case {
    const char* json;
    Ref ref;
  };
  Ref dielectric;
  dielectric.base = 0.6, dielectric.metallic = 0, dielectric.roughness = 0.5;
  Ref metal;
  metal.base = 0.9, metal.metallic = 1, metal.roughness = 0.3;
  Ref mixed;
  mixed.base = 0.4, mixed.metallic = 0.3, mixed.roughness = 0.7, mixed.specular = 0.6, mixed.specular_color = 0.5, mixed.ior = 2;
  Ref coat = dielectric;
  coat.clearcoat = 0.8, coat.clearcoat_roughness = 0.2;
  Ref aniso = metal;
  aniso.aniso = 0.7, aniso.rot = 0.6;
  Ref trans = dielectric;
  trans.transmission = 0.5, trans.dt = 0;
  Ref diffuse_t = dielectric;
  diffuse_t.dt = 0.4;
  const Case cases[] = {
      {R"({"type":"gltf_pbr","base_color":0.6,"metallic":0,"roughness":0.5})", dielectric},
      {R"({"type":"gltf_pbr","base_color":0.9,"metallic":1,"roughness":0.3})", metal},
      {R"({"type":"gltf_pbr","base_color":0.4,"metallic":0.3,"roughness":0.7,"specular":0.6,"specular_color":0.5,"ior":2})", mixed},
      {R"({"type":"gltf_pbr","base_color":0.6,"metallic":0,"roughness":0.5,"clearcoat":0.8,"clearcoat_roughness":0.2})", coat},
      {R"({"type":"gltf_pbr","base_color":0.9,"metallic":1,"roughness":0.3,"anisotropy_strength":0.7,"anisotropy_rotation":0.6})", aniso},
      {R"({"type":"gltf_pbr","base_color":0.6,"metallic":0,"roughness":0.5,"transmission":0.5})", trans},
      {R"({"type":"gltf_pbr","base_color":0.6,"metallic":0,"roughness":0.5,"diffuse_transmission":0.4})", diffuse_t},
  };
  Pcg32 rng(7);
  for (const Case& c : cases) {
    const BxDF b = parse_material(c.json);
    for (int n = 0; n < 200; ++n) {
      const double mo = 0.05 + 0.95 * rng.next_double(), mi = 0.05 + 0.95 * rng.next_double();
      const Vec3 wo = dir(mo, 2 * kPiD * rng.next_double()), wi = dir(mi, 2 * kPiD * rng.next_double());
      const double want = ref_reflection(c.ref, d3(wo), d3(wi));
      const double got = b.f(wo, wi)[0];
      EXPECT_NEAR(got, want, 2e-4 * want + 1e-6) << c.json << " wo.z " << mo << " wi.z " << mi;
    }
  }
}

TEST(GltfPbr, SheenIsCharlieWithAlbedoScaling) {
  const BxDF b = parse_material(
      R"({"type":"gltf_pbr","base_color":0.5,"metallic":0,"roughness":0.6,"sheen_color":0.9,"sheen_roughness":0.4})");
  Ref r;
  r.base = 0.5, r.metallic = 0, r.roughness = 0.6, r.sheen = 0.9, r.sheen_roughness = 0.4;
  for (const double mo : {0.2, 0.5, 0.9})
    for (const double mi : {0.15, 0.7}) {
      r.sheen_e_o = charlie_albedo_quadrature(mo, 0.4);
      r.sheen_e_i = charlie_albedo_quadrature(mi, 0.4);
      const Vec3 wo = dir(mo, 0.3), wi = dir(mi, 2.5);
      const double want = ref_reflection(r, d3(wo), d3(wi));
      // E is a 24 × 16 table read bilinearly: 1e-3 of the base's share.
      EXPECT_NEAR(b.f(wo, wi)[0], want, 5e-3 * want) << mo << " " << mi;
    }
  // The table itself against the quadrature.
  for (const double a : {0.07, 0.3, 0.55, 1.0})
    for (const double mu : {0.1, 0.3, 0.6, 1.0})
      EXPECT_NEAR(gltf_pbr::charlie_albedo(Float(mu), Float(a)), charlie_albedo_quadrature(mu, a), 5e-3) << a << " " << mu;
}

// Thin-walled transmission is the specular lobe with L mirrored (KHR_materials_transmission),
// tinted by base_color and weighted as the diffuse it replaces.
TEST(GltfPbr, ThinTransmissionMirrorsTheSpecularLobe) {
  const BxDF b = parse_material(R"({"type":"gltf_pbr","base_color":0.7,"metallic":0,"roughness":0.4,"transmission":0.8})");
  const double alpha = 0.16;
  for (const double mo : {0.3, 0.8})
    for (const double mi : {0.2, 0.6}) {
      const Vec3 wo = dir(mo, 0.2), wi = dir(-mi, 2.9);
      const D3 v = d3(wo), lm{wi.x, wi.y, -wi.z};
      const D3 h = unit({v.x + lm.x, v.y + lm.y, v.z + lm.z});
      const double fd = 0.04 + 0.96 * schlick_w(dotd(v, h));
      const double want = 0.7 * 0.8 * (1 - fd) * v_ggx(v, lm, alpha, alpha) * d_ggx(h, alpha, alpha);
      EXPECT_NEAR(b.f(wo, wi)[0], want, 2e-4 * want);
      // Thin-walled: two-sided.
      const Vec3 wo2{wo.x, wo.y, -wo.z}, wi2{wi.x, wi.y, -wi.z};
      EXPECT_NEAR(b.f(wo2, wi2)[0], want, 2e-4 * want);
    }
}

// With a volume, the transmission refracts: Walter et al. 2007 eq. 21 without F (the
// (1 − F_d) is the fresnel_mix's), radiance mode n_wo² K, importance n_wi² K.
TEST(GltfPbr, VolumeTransmissionIsWaltersRefraction) {
  const BxDF b = parse_material(
      R"({"type":"gltf_pbr","base_color":1,"metallic":0,"roughness":0.5,"transmission":1,"thickness":1,"ior":1.5})");
  const double alpha = 0.25, eta = 1.5;
  for (const double mo : {0.3, 0.9})
    for (const double mi : {-0.4, -0.8}) {
      const Vec3 wo = dir(mo, 0.1), wi = dir(mi, 3.0);
      const D3 o = d3(wo), i = d3(wi);
      D3 h = unit({o.x + eta * i.x, o.y + eta * i.y, o.z + eta * i.z});
      if (h.z < 0) h = {-h.x, -h.y, -h.z};
      const double oh = dotd(o, h), ih = dotd(i, h);
      const double g2 = 1 / (1 + (-1 + std::sqrt(1 + alpha * alpha * (1 / (o.z * o.z) - 1))) / 2 +
                             (-1 + std::sqrt(1 + alpha * alpha * (1 / (i.z * i.z) - 1))) / 2);
      const double k = std::abs(oh * ih) * d_ggx(h, alpha, alpha) * g2 / (std::abs(o.z * i.z) * std::pow(oh + eta * ih, 2));
      const double fd = 0.04 + 0.96 * schlick_w(oh);
      // A facet seen from behind by either direction refracts nothing (Walter et al. §4.2).
      const double want = oh > 0 && ih < 0 ? (1 - fd) * k : 0.0;
      EXPECT_NEAR(b.f(wo, wi, TransportMode::Radiance)[0], want, 3e-4 * want) << mo << " " << mi;
      EXPECT_NEAR(b.f(wo, wi, TransportMode::Importance)[0], eta * eta * want, 3e-4 * eta * eta * want);
      // The reverse pair, from inside: the same K, n_wo² = η² in radiance mode.
      EXPECT_NEAR(b.f(wi, wo, TransportMode::Radiance)[0], eta * eta * want, 3e-4 * eta * eta * want);
    }
}

// Sampling matches the pdf, the pdf integrates to the sampled fraction, f is reciprocal and
// finite, for each extension (the validator's properties; energy is measured separately:
// the specification's mixing gains energy at grazing, docs/gltf_pbr.md).
class GltfPbrValidate : public ::testing::TestWithParam<const char*> {};
TEST_P(GltfPbrValidate, SamplingReciprocityAndFiniteness) {
  const BxDF b = parse_material(GetParam());
  const ValidationOptions o = quick();
  for (const auto& p : check_sampling(b, o)) EXPECT_TRUE(p.pass) << p.name << ": " << p.detail;
  const PropertyResult r = check_reciprocity(b, o);
  EXPECT_TRUE(r.pass) << r.detail;
  const PropertyResult f = check_finite(b, o);
  EXPECT_TRUE(f.pass) << f.detail;
  const PropertyResult c = check_consistency(b, o);
  EXPECT_TRUE(c.pass) << c.detail;
}
INSTANTIATE_TEST_SUITE_P(
    Extensions, GltfPbrValidate,
    ::testing::Values(
        R"({"type":"gltf_pbr","base_color":[0.8,0.5,0.2],"metallic":0,"roughness":0.5})",
        R"({"type":"gltf_pbr","metallic":0,"roughness":0,"clearcoat":1})",
        R"({"type":"gltf_pbr","base_color":0.8,"metallic":0,"roughness":0.3,"transmission":1})",
        R"({"type":"gltf_pbr","base_color":[1,0.7,0.4],"metallic":0,"roughness":0.4,"transmission":0.5,"thickness":1,"ior":1.8})",
        R"({"type":"gltf_pbr","metallic":0,"roughness":0.6,"sheen_color":[1,0.5,0.5],"sheen_roughness":0.4,"clearcoat":0.5})",
        R"({"type":"gltf_pbr","metallic":1,"roughness":0.5,"anisotropy_strength":0.8,"anisotropy_rotation":0.7})",
        R"({"type":"gltf_pbr","metallic":0,"roughness":0.5,"diffuse_transmission":0.6,"diffuse_transmission_color":[0.2,0.9,0.4],"alpha":0.4,"alpha_mode":2})"));

// Textures: with_params gives the model the parser makes from the substituted value, and
// only the declared keys vary.
TEST(GltfPbr, TexturedParametersAreTheParsedOnes) {
  const BxDF base = parse_material(R"({"type":"gltf_pbr","metallic":0,"roughness":0.5})");
  const auto rough = varying_param("gltf_pbr", "roughness");
  const auto colour = varying_param("gltf_pbr", "base_color");
  const auto sheen = varying_param("gltf_pbr", "sheen_color");
  ASSERT_TRUE(rough && colour && sheen);
  EXPECT_FALSE(varying_param("gltf_pbr", "ior"));
  EXPECT_FALSE(varying_param("gltf_pbr", "alpha_mode"));
  EXPECT_EQ(material_param_info(*rough).key, "roughness");
  EXPECT_TRUE(material_param_info(*rough).scalar);
  EXPECT_FALSE(material_param_info(*colour).scalar);
  const ParamValue v[] = {{*rough, Color(0.2f)}, {*colour, Color(0.1f, 0.5f, 0.9f)}, {*sheen, Color(0.3f)}};
  const BxDF t = with_params(base, v);
  const BxDF want = parse_material(
      R"({"type":"gltf_pbr","metallic":0,"roughness":0.2,"base_color":[0.1,0.5,0.9],"sheen_color":0.3})");
  const Vec3 wo = dir(0.6, 0.2), wi = dir(0.4, 2.0);
  for (int c = 0; c < 3; ++c) EXPECT_FLOAT_EQ(t.f(wo, wi)[c], want.f(wo, wi)[c]);
}

// The white furnace by quadrature of f (no sampling), against the independent formulas'
// quadrature: the model's albedo is the specification's, including its gain at grazing.
TEST(GltfPbr, WhiteFurnaceIsTheSpecificationsOwn) {
  const BxDF b = parse_material(R"({"type":"gltf_pbr","base_color":1,"metallic":0,"roughness":0.5})");
  Ref r;
  r.base = 1, r.metallic = 0, r.roughness = 0.5;
  std::vector<double> x, wx, y, wy;
  gauss_legendre(48, 0, 1, x, wx);
  gauss_legendre(48, 0, kPiD, y, wy);
  for (const double mo : {1.0, 0.5, 0.1}) {
    const Vec3 wo = dir(mo, 0);
    double got = 0, want = 0;
    for (size_t i = 0; i < x.size(); ++i)
      for (size_t j = 0; j < y.size(); ++j) {
        const Vec3 wi = dir(x[i], y[j]);
        got += 2 * wx[i] * wy[j] * b.f(wo, wi)[0] * x[i];
        want += 2 * wx[i] * wy[j] * ref_reflection(r, d3(wo), d3(wi)) * x[i];
      }
    EXPECT_NEAR(got, want, 3e-4) << mo;
  }
}

}  // namespace gltf_pbr_test
}  // namespace gonio
