// The validator: every built-in model over a sweep of parameters passes every property,
// and each property catches a model broken on purpose — a check that cannot fail
// proves nothing.

#include <gtest/gtest.h>

#include <cmath>
#include <string>

#include "gonio/material.h"
#include "gonio/math/warp.h"
#include "gonio/validate.h"
#include "test_scale.h"

namespace gonio {
namespace {

ValidationOptions options() {
  ValidationOptions o;
  const std::uint64_t probe = test::scaled(1000000, 1);
  o.scale = double(probe) / 1e6;
  return o;
}

const PropertyResult& find(const ValidationReport& r, const std::string& name) {
  for (const auto& p : r.properties)
    if (p.name == name) return p;
  throw std::runtime_error("no property " + name);
}

class ValidateBuiltIn : public ::testing::TestWithParam<const char*> {};

TEST_P(ValidateBuiltIn, EveryPropertyHolds) {
  const char* m = GetParam();
  const ValidationReport r = validate(parse_material(m), options());
  ASSERT_EQ(r.properties.size(), 8u);
  for (const auto& p : r.properties) EXPECT_TRUE(p.pass) << m << ": " << p.name << ": " << p.detail;
}

// Every built-in model over a sweep of its parameters (η below, at and above 1; every
// named metal; both Fresnel forms; extreme colours).
INSTANTIATE_TEST_SUITE_P(
    Sweep, ValidateBuiltIn,
    ::testing::Values(
        R"({"type":"diffuse"})",
      R"({"type":"diffuse","reflectance":[0,0.5,1]})",
      R"({"type":"mirror"})",
      R"({"type":"mirror","reflectance":[0.2,0.9,0.5]})",
      R"({"type":"conductor","material":"Au"})",
      R"({"type":"conductor","material":"Ag"})",
      R"({"type":"conductor","material":"Cu"})",
      R"({"type":"conductor","material":"Al"})",
      R"({"type":"conductor","material":"CuZn","fresnel":"schlick"})",
      R"({"type":"conductor","fresnel":"schlick","f0":1})",
      R"({"type":"conductor","eta":1,"k":0})",
      R"({"type":"dielectric"})",
      R"({"type":"dielectric","eta":0.6666667})",
      R"({"type":"dielectric","eta":1})",
      R"({"type":"dielectric","eta":1.0001})",
      R"({"type":"dielectric","eta":2.4})",
      R"({"type":"dielectric","eta":1.333})",
      // The limits of the accepted index range.
      R"({"type":"dielectric","eta":0.0001})",
      R"({"type":"dielectric","eta":10000})",
      R"({"type":"conductor","eta":10000,"k":10000})",
      R"({"type":"conductor","eta":0.0001,"k":0})",
      // Microfacet models: roughness from 0.01 to 1, both distributions, anisotropy,
      // η below and above 1, energy compensation.
      R"({"type":"roughconductor","alpha":0.01,"material":"Au"})",
      R"({"type":"roughconductor","alpha":0.2,"material":"Cu"})",
      R"({"type":"roughconductor","alpha":1,"material":"Al"})",
      R"({"type":"roughconductor","alpha":[0.05,0.5],"material":"Ag"})",
      R"({"type":"roughconductor","alpha":0.3,"distribution":"beckmann","eta":1.5,"k":3})",
      R"({"type":"roughconductor","alpha":[0.6,0.1],"distribution":"beckmann","fresnel":"schlick","f0":0.9})",
      R"({"type":"roughconductor","alpha":0.5,"fresnel":"schlick","f0":1,"multiscatter":true})",
      R"({"type":"roughconductor","alpha":0.1,"distribution":"beckmann","material":"Au","multiscatter":true})",
      R"({"type":"roughdielectric","alpha":0.01})",
      R"({"type":"roughdielectric","alpha":0.2,"eta":1.33})",
      R"({"type":"roughdielectric","alpha":1,"eta":1.5})",
      R"({"type":"roughdielectric","alpha":0.3,"eta":0.7})",
      R"({"type":"roughdielectric","alpha":[0.05,0.4],"eta":2.4})",
      R"({"type":"roughdielectric","alpha":0.2,"distribution":"beckmann","eta":1.5})",
      R"({"type":"roughdielectric","alpha":[0.5,0.1],"distribution":"beckmann","eta":0.7})",
      R"({"type":"roughdielectric","alpha":0.3,"eta":1})",
      R"({"type":"roughdielectric","alpha":0.3,"eta":1.0001})",
      R"({"type":"roughdielectric","alpha":0.3,"eta":1.004})",
      R"({"type":"roughdielectric","alpha":1,"eta":1.5,"multiscatter":true})",
      R"({"type":"roughdielectric","alpha":0.3,"eta":0.7,"multiscatter":true})",
      R"({"type":"roughdielectric","alpha":0.5,"distribution":"beckmann","eta":1.33,"multiscatter":true})",
      R"({"type":"roughdielectric","alpha":1,"eta":1.05,"multiscatter":true})",
      R"({"type":"roughdielectric","alpha":0.05,"eta":2.4,"multiscatter":true})",
      // The classic models and the layered and blended ones.
      R"({"type":"orennayar","sigma":20})",
      R"({"type":"orennayar","reflectance":[1,0.5,0],"sigma":60,"model":"full"})",
      R"({"type":"phong","kd":0.5,"ks":0.5,"exponent":1})",
      R"({"type":"phong","kd":0,"ks":1,"exponent":1000})",
      R"({"type":"blinnphong","kd":0.3,"ks":0.7,"exponent":0})",
      R"({"type":"blinnphong","kd":0,"ks":1,"exponent":2000})",
      R"({"type":"ward","kd":0.2,"ks":0.8,"alpha":[0.05,0.4]})",
      R"({"type":"ward","kd":0,"ks":1,"alpha":0.01})",
      R"({"type":"ward","kd":0,"ks":1,"alpha":1})",
      R"({"type":"ashikhminshirley","rd":0.5,"rs":0.3,"nu":1000,"nv":10})",
      R"({"type":"ashikhminshirley","rd":1,"rs":0,"nu":1,"nv":1})",
      R"({"type":"plastic","reflectance":0.8})",
      R"({"type":"plastic","reflectance":1,"eta":2.4})",
      R"({"type":"plastic","reflectance":[0.9,0.5,0.1],"alpha":0.2})",
      R"({"type":"plastic","reflectance":0.5,"alpha":[0.02,0.3],"distribution":"beckmann"})",
      R"({"type":"blend","weight":0.3,"bsdfs":[{"type":"diffuse"},{"type":"dielectric"}]})",
      R"({"type":"blend","weight":0.7,"bsdfs":[{"type":"roughconductor","alpha":0.2,"material":"Au"},{"type":"plastic"}]})"));

// --- models broken on purpose, each through the extension point -----------------------

// Lambert-shaped base that the broken variants modify: f = k/π, cosine sampling.
class BaseLambert : public CustomBxDF {
 public:
  explicit BaseLambert(Float k = 0.5f) : k_(k) {}
  BxDFFlags flags() const override { return BxDFFlags::DiffuseReflection; }
  Color f(const Vec3& wo, const Vec3& wi, TransportMode) const override {
    return wo.z * wi.z > 0 ? Color(k_ * kInvPi) * shape(wo, wi) : Color{};
  }
  Float pdf(const Vec3& wo, const Vec3& wi, TransportMode) const override {
    return wo.z * wi.z > 0 ? std::abs(wi.z) * kInvPi : 0;
  }
  std::optional<BSDFSample> sample(const Vec3& wo, Float, Float u1, Float u2, TransportMode m) const override {
    Vec3 wi = square_to_cosine_hemisphere(u1, u2);
    if (wo.z == 0 || wi.z == 0) return std::nullopt;
    if (wo.z < 0) wi.z = -wi.z;
    const Float p = pdf(wo, wi, m);
    return BSDFSample{wi, f(wo, wi, m) * std::abs(wi.z) / p, p, false, Lobe::Reflection, 1};
  }
  virtual Float shape(const Vec3&, const Vec3&) const { return 1; }

 protected:
  Float k_;
};

class NonReciprocal final : public BaseLambert {
  // Depends on wo and wi differently: f(wo, wi) ≠ f(wi, wo).
  Float shape(const Vec3& wo, const Vec3& wi) const override { return 1 + 0.5f * std::abs(wo.z) - 0.5f * std::abs(wi.z); }
};

class EnergyGaining final : public BaseLambert {
 public:
  EnergyGaining() : BaseLambert(1.05f) {}
};

class PdfNotMatchingSample final : public BaseLambert {
 public:
  // Samples cosine-weighted but claims a uniform density (which also integrates to 1).
  Float pdf(const Vec3& wo, const Vec3& wi, TransportMode) const override {
    return wo.z * wi.z > 0 ? kInv2Pi : 0;
  }
};

class PdfWrongIntegral final : public BaseLambert {
 public:
  // The right shape at 80 % of the right size: only the integral reveals it.
  Float pdf(const Vec3& wo, const Vec3& wi, TransportMode m) const override {
    return 0.8f * BaseLambert::pdf(wo, wi, m);
  }
};

class NanAtGrazing final : public BaseLambert {
 public:
  Color f(const Vec3& wo, const Vec3& wi, TransportMode m) const override {
    // The classic mistake: dividing by cos θ without a guard.
    return BaseLambert::f(wo, wi, m) * (std::abs(wi.z) / std::abs(wi.z));
  }
};

class WeightNotFCosOverPdf final : public BaseLambert {
 public:
  std::optional<BSDFSample> sample(const Vec3& wo, Float a, Float b, Float c, TransportMode m) const override {
    auto s = BaseLambert::sample(wo, a, b, c, m);
    if (s) s->weight *= 1.1f;
    return s;
  }
};

class Anisotropic final : public BaseLambert {
  // Brighter along x, yet (by default) declared isotropic.
  Float shape(const Vec3& wo, const Vec3& wi) const override {
    return 1 + 0.3f * (wo.x * wo.x + wi.x * wi.x) - 0.3f * (wo.y * wo.y + wi.y * wi.y);
  }
};

class WrongClosedFormAlbedo final : public BaseLambert {
 public:
  std::optional<DirectionalAlbedo> albedo(const Vec3&, TransportMode) const override {
    return DirectionalAlbedo{Color(0.45f), Color{}};  // true value 0.5
  }
};

TEST(Validate, CatchesANonReciprocalModel) {
  const auto r = check_reciprocity(make_user_bxdf<NonReciprocal>(), options());
  EXPECT_FALSE(r.pass) << r.detail;
  EXPECT_GT(*r.figure, 0.1);
  EXPECT_TRUE(check_reciprocity(make_user_bxdf<BaseLambert>(), options()).pass);
}

TEST(Validate, CatchesAnEnergyGainingModel) {
  const auto r = check_energy(make_user_bxdf<EnergyGaining>(), options());
  EXPECT_FALSE(r.pass) << r.detail;
  EXPECT_NEAR(*r.figure, 1.05, 0.01);
  EXPECT_TRUE(check_energy(make_user_bxdf<BaseLambert>(), options()).pass);
}

TEST(Validate, CatchesSamplingThatDoesNotMatchThePdf) {
  const auto r = check_sampling(make_user_bxdf<PdfNotMatchingSample>(), options());
  EXPECT_EQ(r[0].name, "chi2");
  EXPECT_FALSE(r[0].pass) << r[0].detail;
  const auto good = check_sampling(make_user_bxdf<BaseLambert>(), options());
  EXPECT_TRUE(good[0].pass) << good[0].detail;
  EXPECT_TRUE(good[1].pass) << good[1].detail;
}

TEST(Validate, CatchesAPdfThatDoesNotIntegrateToTheSampledFraction) {
  const auto r = check_sampling(make_user_bxdf<PdfWrongIntegral>(), options());
  EXPECT_EQ(r[1].name, "pdf_integral");
  EXPECT_FALSE(r[1].pass) << r[1].detail;
  EXPECT_NEAR(*r[1].figure, 0.2, 0.01);
}

TEST(Validate, CatchesNanAtGrazing) {
  const auto r = check_finite(make_user_bxdf<NanAtGrazing>(), options());
  EXPECT_FALSE(r.pass) << r.detail;
  EXPECT_NE(r.detail.find("f not finite"), std::string::npos) << r.detail;
  EXPECT_TRUE(check_finite(make_user_bxdf<BaseLambert>(), options()).pass);
}

TEST(Validate, CatchesWeightsThatAreNotFCosOverPdf) {
  const auto r = check_consistency(make_user_bxdf<WeightNotFCosOverPdf>(), options());
  EXPECT_FALSE(r.pass) << r.detail;
  EXPECT_TRUE(check_consistency(make_user_bxdf<BaseLambert>(), options()).pass);
}

TEST(Validate, CatchesAClosedFormAlbedoTheSamplingDisagreesWith) {
  const auto r = check_consistency(make_user_bxdf<WrongClosedFormAlbedo>(), options());
  EXPECT_FALSE(r.pass) << r.detail;
}

TEST(Validate, CatchesAnAnisotropicModelDeclaredIsotropic) {
  const auto r = check_isotropy(make_user_bxdf<Anisotropic>(), options());
  EXPECT_FALSE(r.pass) << r.detail;
  EXPECT_TRUE(check_isotropy(make_user_bxdf<BaseLambert>(), options()).pass);
}

TEST(Validate, CatchesAModelThatIsNotTheBlendItClaims) {
  // A blend with weight 0.4, claimed to be the 0.3 blend of the same parts.
  const BxDF a = parse_material(R"({"type":"diffuse","reflectance":0.9})");
  const BxDF b = parse_material(R"({"type":"mirror","reflectance":0.2})");
  const BxDF real = parse_material(
      R"({"type":"blend","weight":0.4,"bsdfs":[{"type":"diffuse","reflectance":0.9},{"type":"mirror","reflectance":0.2}]})");
  const auto r = check_linearity(real, a, b, 0.3f, options());
  EXPECT_FALSE(r.pass) << r.detail;
  EXPECT_TRUE(check_linearity(real, a, b, 0.4f, options()).pass);
  EXPECT_TRUE(check_linearity(real, options()).pass);
}

TEST(Validate, PropertiesThatDoNotApplyPassWithoutAFigure) {
  const auto r = validate(parse_material(R"({"type":"mirror"})"), options());
  EXPECT_FALSE(find(r, "reciprocity").figure.has_value());
  EXPECT_FALSE(find(r, "chi2").figure.has_value());
  EXPECT_FALSE(find(r, "linearity").figure.has_value());
  EXPECT_TRUE(r.pass());
}

TEST(Validate, DeterministicForAGivenSeed) {
  const BxDF m = make_user_bxdf<BaseLambert>();
  const auto a = check_sampling(m, options()), b = check_sampling(m, options());
  EXPECT_EQ(*a[0].figure, *b[0].figure);
}

}  // namespace
}  // namespace gonio
